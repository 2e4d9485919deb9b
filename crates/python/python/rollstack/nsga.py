"""The nonsmooth generalized-α method (Capobianco, Harsch, Eugster and Leine 2021; §4.2,
App. H), on the benchmark systems of the ``nsga`` crate whose answers are known."""

from __future__ import annotations

from typing import Any, Dict, Optional, Sequence

from . import _rollstack
from ._args import count, in_range, number, number_list, optional_number, positive

__all__ = ["ball", "work_precision"]


def ball(
    case: int,
    dt: float = 2e-3,
    scheme: str = "nsga",
    rho_inf: float = 0.5,
    prox_constant: Optional[float] = None,
) -> Dict[str, Any]:
    """The paper's rotating bouncing ball, case 1-4, with the nonsmooth generalized-α
    scheme (``"nsga"``) or Moreau-Jean (``"moreau"``). Returns a dict: ``report`` (as
    ``rollstack nsga ball --case N --json``: first impact, rolling onset, rest, final
    velocity against the closed form) and the trajectory ``t`` (N,), ``q``, ``u``
    (N, 3), ``p_n`` (N,), ``iterations`` (N,) int64.

    Raises ``ValueError`` for a case outside 1-4, dt outside (0, 0.1], ρ∞ outside
    [0, 1]; :class:`rollstack.SolverError` when a step fails.
    """
    case = count("case", case)
    if not 1 <= case <= 4:
        raise ValueError(f"case must be 1, 2, 3 or 4, got {case}")
    return _rollstack.nsga_ball(
        case,
        number("dt", dt),
        scheme,
        number("rho_inf", rho_inf),
        optional_number("prox_constant", prox_constant),
    )


def work_precision(
    system: str,
    dts: Sequence[float] = (0.008, 0.004, 0.002, 0.001, 0.0005, 0.00025),
    rho_inf: Sequence[float] = (0.0, 0.5, 0.8, 1.0),
    repeat: int = 3,
) -> Dict[str, Any]:
    """Error against CPU time for ``"ball"``, ``"oscillator"`` or ``"incline"``, NSGA
    for each ρ∞ beside Moreau-Jean, each time the best of ``repeat`` runs: the
    ``rows``, ``orders``, ``reference_dt`` and ``reference_events`` of
    ``rollstack nsga work-precision --json``. Each order is fitted only over the smallest
    Δt whose runs follow the contact events of a reference run (``{"status": "fitted",
    "order": ..., "dts": [...]}``), or is ``{"status": "not_in_asymptotic_range"}``. Runs with the GIL released; raises
    ``KeyboardInterrupt`` on Ctrl-C (checked every 20 ms, the study stopping between two
    of its runs)."""
    # Checked here so that the errors name the parameters, not the library's dt and ρ∞.
    dts = [positive(f"dts[{i}]", dt) for i, dt in enumerate(number_list("dts", dts))]
    for i, dt in enumerate(dts):
        in_range(f"dts[{i}]", dt, 0.0, 0.1)
    rhos = [in_range(f"rho_inf[{i}]", r, 0.0, 1.0)
            for i, r in enumerate(number_list("rho_inf", rho_inf))]
    return _rollstack.nsga_work_precision(system, dts, rhos, count("repeat", repeat))
