"""Rotations (§2.2, App. A): conversions between axis-angle (2.2.1)₁, unit quaternions
(2.2.1)₂, rotation matrices and the angles of the 12 Euler sets (A.1.2), from the
``rotations`` crate.

Representations are named as on the command line: ``"axis-angle"`` (values
``[x, y, z, theta]``: the axis, need not be unit, and the angle), ``"quaternion"``
(``[q0, q1, q2, q3]``, scalar first, normalised before use), ``"matrix"`` (3 x 3, entry
``[i][j]`` = Eᵢ · R Eⱼ) and ``"euler:I-J-K"`` (three angles, R = R(a1, Eᵢ) R(a2, Eⱼ)
R(a3, Eₖ); at a singular a2 the first angle is set to 0 and the third carries the
rotation). Every function takes arrays batched over leading axes: shape ``(..., 4)``,
``(..., 3, 3)`` or ``(..., 3)``, and returns float64 arrays.
"""

from __future__ import annotations

from typing import Any, Dict, List

import numpy as np

from . import _rollstack

__all__ = [
    "convert",
    "to_matrix",
    "from_matrix",
    "axis_angle_to_quaternion",
    "quaternion_to_axis_angle",
    "euler_to_matrix",
    "matrix_to_euler",
    "report",
    "euler_sets",
]


def convert(values: Any, from_: str, to: str) -> np.ndarray:
    """Converts rotations from one representation to another, row by row.

    ``values`` has the shape ``(..., k)`` (``(..., 3, 3)`` for matrices) of ``from_``;
    the result has the leading shape and the trailing shape of ``to``. Axis-angle output
    is canonical (θ in [0, π], E3 at θ = 0); quaternion output has q0 ≥ 0. A matrix is
    accepted within 1e-4 of orthogonal and projected onto the nearest rotation.

    Raises ``ValueError`` for an unknown representation, a wrong shape, a zero axis or
    quaternion, a non-finite value or a matrix that is not a rotation (the message names
    the flat index of the offending rotation).

    >>> convert([0, 0, 1, np.pi / 2], "axis-angle", "quaternion").round(6)
    array([0.707107, 0.      , 0.      , 0.707107])
    """
    array = np.ascontiguousarray(values, dtype=np.float64)
    return _rollstack.rotations_convert(array, from_, to)


def to_matrix(values: Any, from_: str) -> np.ndarray:
    """Rotation matrices ``(..., 3, 3)`` of rotations given in ``from_``."""
    return convert(values, from_, "matrix")


def from_matrix(matrices: Any, to: str) -> np.ndarray:
    """The rotations of matrices ``(..., 3, 3)`` in the representation ``to``."""
    return convert(matrices, "matrix", to)


def axis_angle_to_quaternion(values: Any) -> np.ndarray:
    """Quaternions ``(..., 4)`` (scalar first, q0 ≥ 0) of ``[x, y, z, theta]`` rows (2.2.1)."""
    return convert(values, "axis-angle", "quaternion")


def quaternion_to_axis_angle(values: Any) -> np.ndarray:
    """Canonical ``[x, y, z, theta]`` rows of quaternions ``(..., 4)`` (2.2.1)."""
    return convert(values, "quaternion", "axis-angle")


def euler_to_matrix(angles: Any, euler_set: str) -> np.ndarray:
    """Matrices of Euler angles ``(..., 3)`` of the set ``"3-1-3"`` etc. (A.1.2)."""
    return convert(angles, "euler:" + euler_set, "matrix")


def matrix_to_euler(matrices: Any, euler_set: str) -> np.ndarray:
    """Angles ``(..., 3)`` of the Euler set ``"3-1-3"`` etc. of matrices (App. A)."""
    return convert(matrices, "matrix", "euler:" + euler_set)


def report(values: Any, from_: str) -> Dict[str, Any]:
    """One rotation in every representation: the dict ``rollstack rotation --from FROM
    --values ... --json`` prints (``rotations::rotation_report``: matrix, quaternion,
    axis-angle, the 12 Euler sets with their round-trip errors)."""
    flat = [float(v) for v in np.asarray(values, dtype=np.float64).ravel()]
    return _rollstack.rotations_report(flat, from_)


def euler_sets() -> List[str]:
    """The names of the 12 Euler sets: ``"1-2-3"``, ..., ``"3-2-3"``."""
    return _rollstack.rotations_euler_sets()
