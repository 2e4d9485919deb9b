"""Inclined rolling cylinders (Ch. 3, App. D-F), from the ``cylinders`` crate.

The support statics of §3.3 at one inclination (:func:`support`) and as the curves of
Figures 3.3-3.8 (:func:`statics`), the holonomy of §3.4, the Frobenius test, and the
two-cylinder transport of §3.5-3.6 (:func:`pair`), swept over the inclination
(:func:`sweep_pair`, Figure 3.14) and over a push at the tops (:func:`sweep_push`), and
its speed against error (:func:`work_precision`).
"""

from __future__ import annotations

import math
from typing import Any, Callable, Dict, List, Optional, Sequence, Union

from . import _rollstack
from ._args import count, number, number_list, values

__all__ = [
    "support",
    "statics",
    "holonomy_rectangle",
    "holonomy_circle",
    "frobenius",
    "frobenius_test",
    "pair",
    "sweep_pair",
    "sweep_push",
    "work_precision",
]


def support(
    theta: float,
    r_over_h: float = 0.1,
    mu: float = 0.2,
    mass: Optional[float] = None,
    gravity: float = 9.81,
) -> Dict[str, Any]:
    """Support statics of a cylinder rolled on its rim at inclination ``theta``
    (3.3.8)-(3.3.20) (μ in (3.3.8), ERRATA): the dict of ``rollstack cylinder support
    --json`` (normal forces at the friction limits, the least force; in newtons when
    ``mass`` is given)."""
    return _rollstack.cylinders_support(
        number("theta", theta),
        number("r_over_h", r_over_h),
        number("mu", mu),
        mass,
        number("gravity", gravity),
    )


def statics(r_over_h: float = 0.1, mu: float = 0.2, points: int = 721) -> Dict[str, Any]:
    """The support-force curves of Figures 3.3, 3.4, 3.5, 3.7 and 3.8 (§3.3, corrected per
    ERRATA 9-11) at ``points`` - 1 inclinations ϑ_k = (π/2) k / points: what ``rollstack
    cylinder statics --r-over-h R --mu M --points N --out DIR`` writes to its CSV files,
    as one dict.

    ``figure_3_3`` (r/h = ``r_over_h``, μ = ``mu``), each member of ``figure_3_4`` (μ
    fixed, r/h = 0, 0.05, 0.1, 0.15) and of ``figure_3_5`` (r/h fixed, μ = 0 … 0.6) has
    ``r_over_h``, ``mu`` and ``rows``: ``theta`` with N/mg at F_f = +μN e′2
    (``n_over_mg_plus``, (3.3.8)₊), on a smooth plane (``n_over_mg_smooth``, (3.3.10)) and
    at F_f = −μN e′2 (``n_over_mg_minus``, (3.3.8)₋), None where no positive N exists:
    the values :func:`support` gives at that ϑ. ``minimum_force`` has per ϑ the
    unconstrained minimum (3.3.15) on the circle (3.3.20), whether it is ``admissible``
    and the ``minimum`` over the admissible forces (3.3.15)-(3.3.19) (None without a
    support); ``circle`` is the circle BC and ``self_balancing_theta`` ϑ of point D,
    arctan(2r/h).

    Raises ``ValueError`` naming the parameter for a negative or NaN ``r_over_h`` or
    ``mu``, ``points`` outside [3, 100000], or a value of the wrong type.
    """
    return _rollstack.cylinders_statics(
        number("r_over_h", r_over_h), number("mu", mu), count("points", points)
    )


def holonomy_rectangle(
    theta: float,
    phi1: float,
    phi2: float,
    s: float = 0.0,
    case: str = "I",
    cw: bool = False,
    psi0: float = 0.0,
    r_over_h: float = 0.12,
    max_step: float = 1e-3,
) -> Dict[str, Any]:
    """Δφ when the contact point P of a cylinder inclined at ``theta`` (point contact:
    0 < θ < π/2) traces a rectangle of sides rφ1/2, rφ2/2: the nine-rotation product
    (3.4.3) against rolling the cylinder along the path (Figure 3.10).

    Returns a dict: ``report`` (as ``rollstack cylinder holonomy rectangle --json``) and
    the rolled trace: ``t``, ``phi`` (N,), ``center``, ``contact``, ``rim_point``
    (N, 3). ``case`` is ``"I"`` (e'2 outward) or ``"II"`` (inward).
    """
    return _rollstack.cylinders_holonomy_rectangle(
        number("theta", theta),
        number("phi1", phi1),
        number("phi2", phi2),
        number("s", s),
        case,
        bool(cw),
        number("psi0", psi0),
        number("r_over_h", r_over_h),
        number("max_step", max_step),
    )


def holonomy_circle(
    ell: float,
    theta: float,
    h: Optional[float] = None,
    r_over_h: Optional[float] = None,
    r: float = 1.0,
    case: str = "I",
    cw: bool = False,
    max_step: float = 1e-3,
) -> Dict[str, Any]:
    """Δφ when P traces a circle of radius ``ell`` (3.4.10)-(3.4.16) (ERRATA 15),
    against rolling once around it (Figure 3.12); the height is ``h`` or
    ``r / r_over_h``. Returns ``report`` (as ``rollstack cylinder holonomy circle
    --json``) and the rolled trace, as :func:`holonomy_rectangle`."""
    return _rollstack.cylinders_holonomy_circle(
        number("ell", ell),
        number("theta", theta),
        h,
        r_over_h,
        number("r", r),
        case,
        bool(cw),
        number("max_step", max_step),
    )


def frobenius(
    system: str = "single",
    config: str = "generic",
    theta: float = 0.4,
    heading: float = 0.5,
    contact_at: Optional[float] = None,
    r: float = 0.1143,
    h: float = 1.2954,
) -> Dict[str, Any]:
    """The Frobenius test (App. D) of a bundled constraint system: ``"single"`` (one
    cylinder, v_P = 0), ``"pair7"`` (Π1..Π7 of (3.5.13)) or ``"pair9"`` (App. F, the
    rank claim corrected, ERRATA), in the ``"generic"`` or ``"touching"`` configuration:
    the dict of ``rollstack cylinder frobenius --json``. ``contact_at`` (pairs only,
    default 0.3) is where the two cylinders touch along their axes; a NaN or infinite
    value, or one given for ``"single"``, raises ``ValueError``."""
    return _rollstack.cylinders_frobenius(
        system, config, number("theta", theta), number("heading", heading),
        None if contact_at is None else number("contact_at", contact_at),
        number("r", r),
        number("h", h),
    )


def frobenius_test(
    constraint_matrix: Callable[[list], Any], q: Sequence[float], step: float = 1e-6
) -> Dict[str, Any]:
    """The Frobenius test (App. D, the skew matrices S^Γ of (D.1.5)) of your own Pfaffian
    system W(q) q̇ = 0 at the configuration ``q``.

    ``constraint_matrix(q)`` returns W(q) as an (m, n) array (n = ``len(q)``); its
    derivatives are taken by central differences of step ``step``. A NaN or infinite
    entry of W or of a derivative raises ``ValueError`` (never a rank-0 verdict). Returns the report of
    ``cylinders::frobenius::report_from``: rank, nullity, singular values, the largest
    |aᵀ S^Γ b| per constraint over the null space, and ``integrable`` per constraint.
    """
    return _rollstack.cylinders_frobenius_callable(
        constraint_matrix, number_list("q", q), number("step", step)
    )


def pair(
    theta: float,
    dt: float = 2e-3,
    steps: int = 2000,
    spin: float = -6.0 * math.pi,
    ramp: Optional[float] = None,
    mu_floor: float = 1.0,
    mu_mutual: float = 0.4,
    push_over_mg: float = 0.0,
    rho_inf: float = 0.5,
    force: bool = False,
) -> Dict[str, Any]:
    """Two touching gas cylinders rolled together (§3.5-3.6, (3.5.1)-(3.5.13)), both
    inclined at ``theta`` with opposite headings, tops held at their height, cylinder I
    spun at ``spin`` rad/s (from t = 0, or over ``ramp`` seconds), on the nonsmooth
    generalized-α stepper with real index sets for the rims on the floor (friction
    ``mu_floor``) and the contact between the cylinders (``mu_mutual``); an optional
    horizontal push ``push_over_mg`` at each top. Returns ``report`` (the dict of
    ``rollstack cylinder pair --json``: ``n_over_mg``, ``f3_over_mg``,
    ``contact_normal_force``, ``static_error`` against (3.3.10), ``drift``,
    ``min_gap``, ...) and the trajectory as numpy arrays: ``t`` (n,), ``q`` (n, 12),
    ``spin_rates`` (n, 2), ``n_over_mg`` (n, 2), ``f3_over_mg`` (n, 2),
    ``contact_normal_force`` (n,), ``gaps`` (n, 3) (floor I, floor II, mutual). Bad
    input raises ``ValueError``; a step the solver cannot take, ``SolverError``. Runs
    with the GIL released (about 8 µs per step); Ctrl-C stops it after the current step
    and raises ``KeyboardInterrupt``. A run estimated (on its first 100 steps) to take
    longer than ten minutes raises ``ValueError`` before it starts, as ``rollstack
    cylinder pair`` refuses it, unless ``force=True``."""
    return _rollstack.cylinders_pair(
        number("theta", theta),
        number("dt", dt),
        count("steps", steps),
        number("spin", spin),
        None if ramp is None else number("ramp", ramp),
        number("mu_floor", mu_floor),
        number("mu_mutual", mu_mutual),
        number("push_over_mg", push_over_mg),
        number("rho_inf", rho_inf),
        bool(force),
    )


def sweep_pair(
    theta: Union[str, float, Sequence[float]],
    dt: float = 2e-3,
    steps: int = 2000,
    spin: float = -6.0 * math.pi,
    force: bool = False,
) -> List[Dict[str, Any]]:
    """Figure 3.14: the transport of :func:`pair` (the thesis's settings, cylinder I spun
    at ``spin`` rad/s) at each inclination of ``theta``, in parallel (rayon, the GIL
    released), rows in input order: the rows of ``rollstack cylinder sweep pair --theta
    THETA --json`` (``theta``, ``n_over_mg``, ``f3_over_mg``,
    ``contact_normal_force``, ``n_over_mg_static`` of (3.3.10), ``static_error``,
    ``drift``, ``min_gap``, ``steps``, ``error``: a run the solver stops is its row's
    error).

    ``theta`` is in radians: one number, a sequence, or the command line's text
    (``"10deg:40deg:10deg"``, ``"pi/6,pi/4"``), each in (arctan(2r/h), π/2). Every
    value is checked before any run; ``ValueError`` names the parameter. Runs estimated
    (on the first 100 steps) to take longer than ten minutes in all are refused unless
    ``force=True``. Ctrl-C stops the runs after their current step and raises
    ``KeyboardInterrupt``.
    """
    return _rollstack.cylinders_sweep_pair(
        values("theta", theta),
        number("dt", dt),
        count("steps", steps),
        number("spin", spin),
        bool(force),
    )


def sweep_push(
    theta: Union[str, float, Sequence[float]],
    push: Union[str, float, Sequence[float]] = "0:0.5:0.01",
    mu_floor: float = 0.2,
    dt: float = 2e-3,
    steps: int = 100,
    force: bool = False,
) -> List[Dict[str, Any]]:
    """The push at which a rim starts to slip, against ϑ: at each inclination of
    ``theta`` the pushes P/mg of ``push`` are applied along e′2 at each top (floor
    friction μ_s = ``mu_floor``), moving away from 0, until a rim slips; the onset is
    compared with the statics μ_s N₋/mg of (3.3.8)₋ (P > 0) or −μ_s N₊/mg of (3.3.8)₊
    (P < 0), and the minimum applied force (3.3.15)-(3.3.19) is checked by three more
    runs. The rows of ``rollstack cylinder sweep push --theta THETA --json``
    (``onset_over_mg``, ``static_onset_over_mg``, ``agrees``, ``minimum_force``, ...),
    in parallel (the GIL released), in input order.

    ``theta`` and ``push`` take one number, a sequence or the command line's text
    (``"0:0.5:0.01"``), ``theta`` in radians. Every value is checked before any run;
    ``ValueError`` names the parameter. Runs estimated to take longer than ten minutes in
    all (every push of every row counted) are refused unless ``force=True``. Ctrl-C stops
    the runs after their current step and raises ``KeyboardInterrupt``.
    """
    return _rollstack.cylinders_sweep_push(
        values("theta", theta),
        values("push", push),
        number("mu_floor", mu_floor),
        number("dt", dt),
        count("steps", steps),
        bool(force),
    )


def work_precision(
    theta: float = math.pi / 6,
    dts: Sequence[float] = (8e-3, 4e-3, 2e-3, 1e-3),
    reference_factor: float = 4.0,
    repeat: int = 3,
    force: bool = False,
) -> Dict[str, Any]:
    """Speed against error for the transport of :func:`pair` spun up over 0.5 s at
    inclination ``theta`` (rad), to t = 1.2 s: each Δt of ``dts`` (s) run by the
    nonsmooth generalized-α method and by Moreau-Jean, measured against a
    generalized-α run with Δt = min(dts)/``reference_factor`` (``error``), against the
    statics (3.3.10) (``static_error``), by the drift of the constraints that hold the
    pair (``drift``) and the rims' floor slip at the end (``final_floor_slip``), against
    solver time (the fastest of ``repeat`` runs). Returns the dict of ``rollstack
    cylinder work-precision --json``: ``rows``, ``orders`` (per scheme: ``status``
    ``"fitted"`` or ``"not_in_asymptotic_range"``, ``order``, ``dts``; an order is
    fitted only over the smallest Δt whose runs follow the reference's contact events),
    ``reference_dt``, ``reference_events``, ``n_over_mg_static``, ... Bad input raises
    ``ValueError`` naming the parameter; a study estimated to take longer than ten
    minutes is refused unless ``force=True``. Runs with the GIL released; Ctrl-C stops
    it and raises ``KeyboardInterrupt``."""
    return _rollstack.cylinders_work_precision(
        number("theta", theta),
        number_list("dts", dts),
        number("reference_factor", reference_factor),
        count("repeat", repeat),
        bool(force),
    )
