"""The rolling sphere (Ch. 2, App. B, C), from the ``holonomy`` crate.

A sphere of radius R rolls without slipping on a plane; its centre travels a closed
rectangle of sides ϑ = H1/R and φ2 = H2/R (units of R), starting φ1 along the side
(0 ≤ φ1 ≤ φ2), counter-clockwise unless ``cw``. The holonomy is the rotation the sphere
has turned by after one circuit.
"""

from __future__ import annotations

from typing import Any, Dict, Optional, Sequence

import numpy as np

from . import _rollstack

__all__ = ["holonomy", "plan", "euler_plan", "roll"]


def holonomy(theta: float, phi1: float, phi2: float, cw: bool = False) -> Dict[str, Any]:
    """The holonomy of one rectangle, (2.4.2)-(2.4.6) (the factor 2 of (2.4.6),
    ERRATA 1): the dict of ``rollstack sphere holonomy --json`` (matrix, quaternion,
    axis and angle ψ (2.4.5), the no-holonomy families).

    Raises ``ValueError`` for negative or non-finite sides, or φ1 outside [0, φ2].
    """
    return _rollstack.sphere_holonomy(float(theta), float(phi1), float(phi2), bool(cw))


def plan(angle: float, axis: Sequence[float]) -> Dict[str, Any]:
    """Every rectangle whose holonomy is the rotation by ``angle`` about ``axis``
    (2.4.12, App. C): the dict of ``rollstack sphere plan --angle A --axis X,Y,Z
    --json``: ``rectangles`` (each with ϑ, φ1, φ2, direction, placement, waypoints,
    path length and error) and the index of the ``shortest``.

    Raises ``ValueError`` for a zero or non-finite axis, or a rotation no rectangle
    produces.
    """
    ax = [float(v) for v in axis]
    if len(ax) != 3:
        raise ValueError(f"axis needs three numbers, got {len(ax)}")
    return _rollstack.sphere_plan(float(angle), ax)


def euler_plan(euler_set: str, angles: Sequence[float]) -> Dict[str, Any]:
    """The Euler three-rectangle planner (§2.5): three rectangles, one per Euler angle of
    the set ``"3-1-3"`` etc., with their waypoints: the dict of ``rollstack sphere
    euler-plan --set SET --angles A1,A2,A3 --json``."""
    a = [float(v) for v in angles]
    if len(a) != 3:
        raise ValueError(f"angles needs three numbers, got {len(a)}")
    return _rollstack.sphere_euler_plan(euler_set, a)


def roll(
    theta: Optional[float] = None,
    phi1: Optional[float] = None,
    phi2: Optional[float] = None,
    cw: bool = False,
    *,
    circle: Optional[float] = None,
    polygon: Optional[Sequence[Sequence[float]]] = None,
    steps: int = 400,
    integrator: str = "exact",
) -> Dict[str, Any]:
    """Rolls once along a closed path, integrating Q' = skewt(ω) Q with ω = E3 × d
    (2.3.4)-(2.3.5), and compares with the closed-form holonomy.

    Give one path: a rectangle (``theta``, ``phi1``, ``phi2``, ``cw``), ``circle=radius``
    or ``polygon=[[x, y], ...]`` (units of R). ``integrator`` is ``"exact"`` or
    ``"rk4"``. Returns a dict: ``report`` (as ``rollstack sphere roll --json``),
    ``label``, and the trajectory: ``s`` (N,), ``centre`` and ``marked_point`` (N, 3),
    ``orientation`` (N, 4) quaternions, scalar first.
    """
    poly = None if polygon is None else [[float(x), float(y)] for x, y in polygon]
    return _rollstack.sphere_roll(
        theta, phi1, phi2, bool(cw), circle, poly, int(steps), integrator
    )
