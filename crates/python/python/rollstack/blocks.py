"""Stacks of 2D blocks on a driven base (Ch. 4, App. G-I), from the ``blockstack``
crate, integrated with impacts and Coulomb friction by the nonsmooth generalized-α
method (§4.2, App. H).

A :class:`Scene` holds the blocks (bottom to top), the base and its prescribed motion,
the contact law, the solver settings and an optional floor: the schema of the
command line's scene files (docs/scenes.md). :func:`simulate` runs one and returns a
:class:`Result` with numpy arrays. :func:`lire`, :func:`shaking` and :func:`sliding`
build the scenes of §4.3-4.5; :func:`sweep_frequency` and :func:`sweep_slide` compute
the rows of Figures 4.6 and 4.7 in parallel, :func:`sweep_scene` any scene over any of
its numeric keys, :func:`fragility` a scene under many records at many intensities
with lognormal fragility curves. :func:`read_record` and :func:`pulse` give the base excitations a
scene's ``[base.x]``, ``[base.y]`` or ``[base.rotation]`` table can play (recorded
accelerograms, one-sine, one-cosine and Ricker pulses) as numpy arrays.

Coordinates: q = (x, y, θ) of each block's centre of mass, u = (ẋ, ẏ, θ̇); interface k
lies between block k-1 (the base for k = 0) and block k; its contact forces are the
normal forces of its left and right gaps (G.2.2) and the friction force (G.3.1).
"""

from __future__ import annotations

import json
import math
import os
from typing import Any, Dict, List, Mapping, Optional, Sequence, Union

import numpy as np

from . import _rollstack
from ._args import count, number, number_list, optional_number, positive
from ._rollstack import SolverError

__all__ = [
    "Scene",
    "Result",
    "simulate",
    "lire",
    "shaking",
    "sliding",
    "scenes",
    "sweep_frequency",
    "sweep_slide",
    "sweep_scene",
    "explore",
    "painleve",
    "work_precision",
    "read_record",
    "pulse",
    "converge",
    "fragility",
]


def _scene_json(tables: Mapping[str, Any]) -> str:
    """The JSON of a scene dict; numpy scalars and arrays become numbers and lists."""

    def plain(value: Any) -> Any:
        if isinstance(value, np.ndarray):
            return value.tolist()
        if isinstance(value, np.generic):
            return value.item()
        raise TypeError(f"a scene value cannot be {type(value).__name__}")

    try:
        return json.dumps(dict(tables), default=plain)
    except (TypeError, ValueError) as e:
        raise ValueError(f"scene: {e}") from None


class Scene:
    """A validated block-stack scene.

    Build one from keyword arguments or a dict with the tables of a scene file
    (``base``, ``blocks``, ``contact``, ``solver``, ``floor``; docs/scenes.md), from a
    TOML file or text, or by the name of a built-in scene::

        Scene(base={"width": 1, "height": 0.2, "motion": "fixed"},
              blocks=[{"width": 1, "height": 0.2, "mass": 1, "x": 0.125}],
              contact={"mu": 0.3}, solver={"dt": 0.01, "t_end": 1})
        Scene.from_dict(d)
        Scene.from_toml("my.toml")        # a path, or TOML text
        Scene.builtin("shaking")          # rollstack blocks scenes

    Keys left out take the defaults of the scene files; unknown keys and invalid values
    (sizes, μ, restitution, overlapping blocks, a floor above the base) raise
    ``ValueError`` with the library's message.
    """

    def __init__(self, _inner: Any = None, **tables: Any) -> None:
        if _inner is not None:
            if tables:
                raise TypeError("Scene() takes either a built scene or keyword tables")
            self._inner = _inner
        else:
            self._inner = _rollstack.blocks_scene_from_json(_scene_json(tables), "scene")

    @classmethod
    def from_dict(cls, tables: Mapping[str, Any], title: str = "scene") -> "Scene":
        """A scene from a dict with the tables of a scene file."""
        return cls(_rollstack.blocks_scene_from_json(_scene_json(tables), title))

    @classmethod
    def from_toml(cls, source: Union[str, "os.PathLike[str]"]) -> "Scene":
        """A scene from a TOML file (a path that exists) or TOML text."""
        if isinstance(source, os.PathLike) or (
            isinstance(source, str) and "\n" not in source and os.path.exists(source)
        ):
            path = os.fspath(source)
            with open(path, encoding="utf-8") as f:
                text = f.read()
            title = os.path.splitext(os.path.basename(path))[0]
            # The paths of the scene's records start from the file's directory.
            return cls(_rollstack.blocks_scene_from_toml(text, title, os.path.dirname(path)))
        return cls(_rollstack.blocks_scene_from_toml(str(source), "scene"))

    @classmethod
    def builtin(cls, name: str) -> "Scene":
        """A built-in scene by name (:func:`scenes` lists them)."""
        return cls(_rollstack.blocks_builtin_scene(name))

    @property
    def toml(self) -> Optional[str]:
        """The scene as TOML (None for the presets built in code)."""
        return self._inner.toml

    @property
    def title(self) -> str:
        """A short name."""
        return self._inner.title

    @property
    def n_blocks(self) -> int:
        """Number of free blocks."""
        return self._inner.n_blocks

    @property
    def warnings(self) -> List[str]:
        """What the scene may do unexpectedly (no floor, ...)."""
        return self._inner.warnings

    def report(self) -> Dict[str, Any]:
        """The scene as used, after defaults: the ``scene`` object of the CLI's JSON."""
        return self._inner.report()

    def __repr__(self) -> str:
        return f"Scene({self.title!r}, {self.n_blocks} block(s))"


def read_record(
    path: Union[str, "os.PathLike[str]"],
    dt: Optional[float] = None,
    scale: float = 1.0,
    scale_to_pga: Optional[float] = None,
    baseline: str = "end-at-rest",
    unit: float = 1.0,
) -> Dict[str, np.ndarray]:
    """A recorded accelerogram as a scene's ``motion = "record"`` plays it.

    ``path`` is a PEER NGA ``.AT2`` file (values in g) or a CSV file (``t,a`` rows, or
    one column ``a`` with its step ``dt``). The record is corrected (``baseline``:
    ``"end-at-rest"`` removes the line from a(t) that makes it end at rest where it
    started, ``"none"`` keeps it), scaled so that its peak is ``scale_to_pga`` (in the
    file's units), then by ``scale``, and each unit of the file's is ``unit`` (9.81 for
    m/s² from g). Returns ``t``, ``a``, ``v``, ``d`` at the samples: a(t) piecewise
    linear, v and d its exact integrals from rest at the first sample. A malformed file
    raises ``ValueError`` naming the file and its line (docs/scenes.md).
    """
    return _rollstack.blocks_read_record(
        os.fspath(path),
        optional_number("dt", dt),
        number("scale", scale),
        optional_number("scale_to_pga", scale_to_pga),
        str(baseline),
        number("unit", unit),
    )


def pulse(
    shape: str,
    amplitude: float,
    period: float,
    t: Any,
    start: float = 0.0,
) -> Dict[str, np.ndarray]:
    """An acceleration pulse of a scene's ``motion = "pulse"`` at the times ``t``.

    ``shape`` is ``"one-sine"`` (a = a_p sin(2πτ/T_p) over one period, τ = t - start),
    ``"one-cosine"`` (a_p cos(2πτ/T_p)) or ``"ricker"`` (a_p (1 - 2s²) exp(-s²),
    s = π(τ - 2T_p)/T_p); ``amplitude`` is a_p, ``period`` T_p. Returns ``t``, ``a``,
    ``v``, ``d``: the velocity and displacement are the exact integrals from rest at
    ``start``.
    """
    times = number_list("t", np.asarray(t, dtype=float).ravel().tolist())
    return _rollstack.blocks_pulse(
        str(shape), number("amplitude", amplitude), number("period", period), times,
        number("start", start),
    )


def scenes() -> Dict[str, str]:
    """The built-in scenes, name -> description (``rollstack blocks scenes``)."""
    return dict(_rollstack.blocks_builtin_scenes())


class Result:
    """What one :func:`simulate` run computed, from t = 0 up to the last step taken.

    Arrays (float64 unless noted; N records: the initial state and one per step; n
    blocks):

    - ``t`` (N,): times;
    - ``q`` (N, n, 3): x, y, θ of each block's centre of mass, bottom to top;
    - ``u`` (N, n, 3): ẋ, ẏ, θ̇;
    - ``forces`` (N, n, 3): per interface (k = 0 between the base and block 1), the
      normal forces of the left and right gaps and the friction force (λ_N, λ_F);
    - ``gaps`` (N, n, 2): the left and right gaps of each interface (G.2.2), NaN where
      the upper block has lost its support (G.2.4, ERRATA 23);
    - ``base`` (N, 3): the prescribed base pose;
    - ``min_gap`` (N,): the smallest gap among the contacts that can close (inf if none);
    - ``energy`` (N,): kinetic plus potential energy of the free blocks;
    - ``iterations`` (N,) int64: Newton iterations of each step.

    ``events`` is a list of dicts in time order, each with ``kind`` and ``t``:
    ``"branch_point"`` (with ``candidates`` and ``distinct``: a step resolved by
    fixed-set re-solves), ``"failure"`` (a block first loses its support, §4.4),
    ``"opening"`` (an interface first opens completely), the failure events of
    ``rollstack blocks run`` with the block (1-based) in ``block`` — ``"support_lost"``
    (with ``on``, e.g. ``"block 1"``, where the block rests on several bodies),
    ``"tipped"`` (past its tipping angle atan(w/h)), ``"touched_floor"`` (a landing),
    ``"height_dropped"`` (the stack's height fell by a block; ``block`` None) — and
    ``"error"`` (with ``message``: the step the solver could not resolve). The deepest
    overlap between two bodies is ``report["max_penetration"]``.

    ``report`` is the dict ``rollstack blocks run --json`` prints (without ``files``
    and ``notes``); ``error`` is its error message or None. :meth:`to_dataframe` gives
    one row per record. ``steps`` is the number of steps taken, ``failure_time`` the
    first time any block lost its support on the block beneath (§4.4), or None.
    """

    t: np.ndarray
    q: np.ndarray
    u: np.ndarray
    forces: np.ndarray
    gaps: np.ndarray
    base: np.ndarray
    min_gap: np.ndarray
    energy: np.ndarray
    iterations: np.ndarray
    events: List[Dict[str, Any]]
    error: Optional[str]
    steps: int
    failure_time: Optional[float]

    _ARRAYS = ("t", "q", "u", "forces", "gaps", "base", "min_gap", "energy", "iterations")

    def __init__(self, raw: Dict[str, Any]) -> None:
        for name in self._ARRAYS:
            setattr(self, name, raw[name])
        self.events = raw["events"]
        self.error = raw["error"]
        self.steps = raw["steps"]
        self.failure_time = raw["failure_time"]
        self._report_json = raw["report_json"]
        self._report: Optional[Dict[str, Any]] = None

    @property
    def report(self) -> Dict[str, Any]:  # type: ignore[override]
        """The dict ``rollstack blocks run --json`` prints, without ``files`` and
        ``notes`` (parsed on first use)."""
        if self._report is None:
            self._report = json.loads(self._report_json)
        return self._report

    @property
    def failure(self) -> Optional[Dict[str, Any]]:
        """The run's failure: its first failure event (``kind``, ``t``, ``block``) of any
        kind (support lost, tipped, touched the floor, height dropped), or None while the
        column stands; ``report["failure"]``, the CLI's ``failure``."""
        return self.report["failure"]

    def to_dataframe(self) -> Any:
        """The trajectory as a pandas DataFrame, one row per record, with the columns of
        the CLI's trajectory.csv (t, x1, y1, theta1, ..., n1a, n1b, f1, ..., base_x,
        min_gap, newton_iterations, energy) plus vx{k}, vy{k}, omega{k}, g{k}a, g{k}b.
        Needs pandas (``pip install pandas``), which is not a dependency of rollstack.
        """
        try:
            import pandas as pd
        except ImportError as e:
            raise ImportError("Result.to_dataframe needs pandas: pip install pandas") from e
        n = self.q.shape[1]
        cols: Dict[str, Any] = {"t": self.t}
        for k in range(n):
            cols[f"x{k + 1}"] = self.q[:, k, 0]
            cols[f"y{k + 1}"] = self.q[:, k, 1]
            cols[f"theta{k + 1}"] = self.q[:, k, 2]
        for k in range(n):
            cols[f"n{k + 1}a"] = self.forces[:, k, 0]
            cols[f"n{k + 1}b"] = self.forces[:, k, 1]
            cols[f"f{k + 1}"] = self.forces[:, k, 2]
        cols["base_x"] = self.base[:, 0]
        cols["min_gap"] = self.min_gap
        cols["newton_iterations"] = self.iterations
        cols["energy"] = self.energy
        for k in range(n):
            cols[f"vx{k + 1}"] = self.u[:, k, 0]
            cols[f"vy{k + 1}"] = self.u[:, k, 1]
            cols[f"omega{k + 1}"] = self.u[:, k, 2]
        for k in range(n):
            cols[f"g{k + 1}a"] = self.gaps[:, k, 0]
            cols[f"g{k + 1}b"] = self.gaps[:, k, 1]
        return pd.DataFrame(cols)

    def __repr__(self) -> str:
        end = float(self.t[-1]) if len(self.t) else 0.0
        return (
            f"<rollstack.blocks.Result: {self.steps} steps to t = {end:.4g}, "
            f"{self.q.shape[1]} block(s), failure_time = {self.failure_time}, "
            f"{len(self.events)} event(s){', error' if self.error else ''}>"
        )


def simulate(
    scene: Scene,
    *,
    t_end: Optional[float] = None,
    prox_constant: Optional[float] = None,
    explore_branches: bool = True,
    last_resort: bool = True,
    stop_at_failure: bool = False,
    low_rank_updates: bool = True,
    force: bool = False,
) -> Result:
    """Simulates ``scene`` from t = 0 to ``t_end`` (default: the scene's
    ``solver.t_end``) with the nonsmooth generalized-α stepper (§4.2, App. H): nsga's
    consistent start (a resting column starts with its static contact forces), then one
    step per Δt with the gaps (G.2.2)-(G.2.3) and slips (G.3.1)-(G.3.2) of App. G.

    Options, as the flags of ``rollstack blocks run``:

    - ``prox_constant``: one constant prox parameter r > 0 for every contact (the
      thesis: 0.3) instead of the scene's choice (default: scaled per constraint);
    - ``explore_branches``: record branch points (the steps that re-solves with fixed
      index sets resolved when Newton cycled; those re-solves are part of every run, so
      the motion is the same either way);
    - ``last_resort``: take a step nothing else resolves as a Moreau-Jean step solved by
      Lemke's method (docs/method.md §8);
    - ``stop_at_failure``: stop at the first loss of support (as the sweeps do);
    - ``low_rank_updates``: where a Newton iterate's index sets differ from those of the
      kept factors in a few rows, update the kept factors instead of factorizing anew
      (docs/method.md §7); ``False`` factorizes every change of sets, as the paper does;
    - ``force``: run even when the run is estimated to take longer than ten minutes
      (the time guard of ``rollstack blocks run``: otherwise such a run raises
      ``ValueError`` with the estimate before it starts).

    Returns a :class:`Result`. Raises ``ValueError`` for bad options (t_end ≤ 0, r ≤ 0),
    :class:`rollstack.SolverError` when the run stops early on a step it cannot resolve
    (its ``result`` attribute holds the :class:`Result` up to that step), and
    ``KeyboardInterrupt`` on Ctrl-C (checked every 20 ms while the run works with the GIL
    released; the run ends within its current step).

    Example::

        from rollstack import blocks
        r = blocks.simulate(blocks.lire(perturb="bottom"), t_end=10)
        r.failure_time, r.q[-1]
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"simulate needs a rollstack.blocks.Scene, got {type(scene).__name__}")
    raw = _rollstack.blocks_simulate(
        scene._inner,
        None if t_end is None else number("t_end", t_end),
        None if prox_constant is None else number("prox_constant", prox_constant),
        bool(explore_branches),
        bool(last_resort),
        bool(stop_at_failure),
        bool(low_rank_updates),
        bool(force),
    )
    result = Result(raw)
    if raw["interrupted"] is not None:
        raise raw["interrupted"]
    if result.error is not None:
        if result.steps == 0 and len(result.t) == 0:
            what = "the simulation could not start"
        else:
            what = f"the simulation stopped at t = {float(result.t[-1]):.6f} after {result.steps} steps"
        err = SolverError(f"{what}: {result.error}")
        err.result = result  # type: ignore[attr-defined]
        raise err
    return result


_PERTURBATIONS = ("none", "bottom", "top")


def lire(blocks: int = 4, perturb: str = "none", floor: bool = False) -> Scene:
    """The Leaning Tower of Lire (§4.3, Figure 4.4): blocks w = 1, h = 0.2, μ = 0.3 in
    the harmonic maximum-overhang configuration (ERRATA 16) on a fixed table; perturbed
    by 0.01 at the ``"bottom"`` block (the whole column collapses) or the ``"top"`` one
    (it topples), or not (``"none"``: an unstable equilibrium). ``floor=True`` stands the
    table on a floor where the blocks land. Simulate with ``t_end=10`` as the CLI."""
    if perturb not in _PERTURBATIONS:
        raise ValueError(f"perturb must be one of {', '.join(_PERTURBATIONS)}, got {perturb!r}")
    return Scene(_rollstack.blocks_lire(count("blocks", blocks), perturb, bool(floor)))


def _base_periods(omega_name: str, omega: Any, steps_per_period: Any, periods: Any) -> float:
    """``omega`` checked, with the time step 2π/(Nω) and the span P·2π/ω it gives: each
    a positive finite number, else ``ValueError`` naming the parameters (the library
    names its ``dt``)."""
    omega = positive(omega_name, omega)
    steps_per_period = positive("steps_per_period", steps_per_period)
    periods = positive("periods", periods)
    period = 2.0 * math.pi / omega
    for what, value in (("time step 2π/(Nω)", period / steps_per_period),
                        ("span P·2π/ω", periods * period)):
        if not (math.isfinite(value) and value > 0):
            raise ValueError(
                f"{omega_name} = {omega!r} with steps_per_period = {steps_per_period!r} and "
                f"periods = {periods!r} gives a {what} of {value!r}, which cannot be stepped"
            )
    return omega


def shaking(
    blocks: int = 4,
    omega: float = 4.0,
    amplitude: float = 0.2,
    mu: float = 0.2,
    steps_per_period: float = 100.0,
    periods: float = 10.0,
    start_with_base: bool = False,
) -> Scene:
    """A column of blocks w = 0.2, h = 0.4 on a base w = 1, h = 0.1 moving as
    x = A sin(ωt) (§4.4, Figures 4.5-4.6); Δt and t_end count in base periods 2π/ω
    (ERRATA 21). The scene of ``rollstack blocks shake``. The blocks start at rest
    (Figure 4.6), or with ``start_with_base=True`` moving with the base (velocity Aω)."""
    return Scene(
        _rollstack.blocks_shaking(
            count("blocks", blocks),
            _base_periods("omega", omega, steps_per_period, periods),
            number("amplitude", amplitude),
            number("mu", mu),
            number("steps_per_period", steps_per_period),
            number("periods", periods),
            bool(start_with_base),
        )
    )


def sliding(blocks: int = 4, v0: float = 1.0, t_end: float = 3.0, mu: float = 0.2) -> Scene:
    """A column on a base pulled at speed ``v0`` (§4.5, Figure 4.7)."""
    return Scene(
        _rollstack.blocks_sliding(
            count("blocks", blocks), number("v0", v0), number("t_end", t_end), number("mu", mu)
        )
    )


def sweep_frequency(
    omegas: Sequence[float],
    *,
    periods: float = 10.0,
    amplitude: float = 0.2,
    blocks: int = 4,
    steps_per_period: float = 100.0,
    mu: float = 0.2,
    prox_constant: Optional[float] = None,
    explore_branches: bool = True,
    last_resort: bool = True,
    t_max: Optional[float] = None,
    low_rank_updates: bool = True,
    branches: int = 1,
    branch_rule: str = "self_consistent",
    force: bool = False,
    convergence: Optional[int] = None,
    ensemble: Optional[int] = None,
) -> List[Dict[str, Any]]:
    """Failure time against the shaking frequency (Figure 4.6): one row per ω, each run
    until the first loss of support or the end of its periods, in parallel (rayon, the
    GIL released), in input order. With ``t_max`` every ω gets that horizon in time
    units instead of ``periods`` (``--t-max``): a fixed number of periods watches a fast
    base for less time than a slow one. The rows of ``rollstack blocks sweep frequency
    --json`` (omega, horizon, outcome, failure_time, inv_failure_time, opening_time,
    steps, error, ...); ``outcome`` is ``failed``, ``no_failure_by_horizon`` or
    ``stopped``, and a run the solver stops has its message in ``error``. Every ω is
    checked before any run (``ValueError``). ``low_rank_updates`` as in :func:`simulate`.

    ``branches`` > 1 (``--branches``) also explores up to that many motions of each run
    (:func:`explore`, its forks found by ``branch_rule``: ``"self_consistent"``, also
    spelled ``"self-consistent"`` as on the command line, or ``"converged"``) and
    reports the smallest, median and largest failure time over them
    (``failure_time_min``, ``failure_time_median``, ``failure_time_max``, with
    ``branches`` and ``failed_branches``). Ctrl-C is seen between the rows' explorations.

    ``convergence`` = K (``--convergence``) also runs each row at Δt/2^k, k = 0…K, with
    ``ensemble`` perturbed runs per magnitude (default 0), and gives each row a
    ``convergence`` dict as the CLI's: ``failure_verdict``, ``failure_rule``,
    ``failure_tolerance``, ``failure_extrapolated``, ``failure_times`` (per level),
    ``outcome_verdict``, ``finest``, ``spread``, ``levels``, ``ensemble``, ``error``.
    Without it the rows have no ``convergence`` key.

    Runs estimated to take longer than ten minutes in all (the time guard of the command
    line, calibrated on the first steps of the costliest run) raise ``ValueError`` before
    any run unless ``force=True``."""
    omegas = number_list("omegas", omegas)
    for i, omega in enumerate(omegas):
        _base_periods(f"omegas[{i}]", omega, steps_per_period, 1.0 if t_max is not None else periods)
    return _rollstack.blocks_sweep_frequency(
        omegas,
        number("periods", periods),
        number("amplitude", amplitude),
        count("blocks", blocks),
        number("steps_per_period", steps_per_period),
        number("mu", mu),
        optional_number("prox_constant", prox_constant),
        bool(explore_branches),
        bool(last_resort),
        None if t_max is None else number("t_max", t_max),
        bool(low_rank_updates),
        count("branches", branches),
        str(branch_rule),
        bool(force),
        *_judged(convergence, ensemble),
    )


def _judged(convergence: Any, ensemble: Any) -> tuple:
    """The ``convergence`` and ``ensemble`` keywords of the sweeps, checked."""
    return (
        None if convergence is None else count("convergence", convergence),
        None if ensemble is None else count("ensemble", ensemble),
    )


def sweep_slide(
    speeds: Sequence[float],
    *,
    t_end: float = 3.0,
    blocks: int = 4,
    mu: float = 0.2,
    prox_constant: Optional[float] = None,
    explore_branches: bool = True,
    last_resort: bool = True,
    low_rank_updates: bool = True,
    branches: int = 1,
    branch_rule: str = "self_consistent",
    force: bool = False,
    convergence: Optional[int] = None,
    ensemble: Optional[int] = None,
) -> List[Dict[str, Any]]:
    """The top block's angle against the speed of the pulled base (Figure 4.7): one row
    per v0, in parallel, in input order: the rows of ``rollstack blocks sweep slide
    --json``. ``branches``, ``branch_rule``, ``force``, ``convergence`` and ``ensemble``
    as in :func:`sweep_frequency`, the spreads being those of the top block's angle."""
    return _rollstack.blocks_sweep_slide(
        number_list("speeds", speeds),
        number("t_end", t_end),
        count("blocks", blocks),
        number("mu", mu),
        optional_number("prox_constant", prox_constant),
        bool(explore_branches),
        bool(last_resort),
        bool(low_rank_updates),
        count("branches", branches),
        str(branch_rule),
        bool(force),
        *_judged(convergence, ensemble),
    )


def sweep_scene(
    scene: Scene,
    set: Mapping[str, Union[str, float, Sequence[float]]],
    *,
    t_end: Optional[float] = None,
    stop_at_failure: bool = False,
    prox_constant: Optional[float] = None,
    explore_branches: bool = True,
    last_resort: bool = True,
    low_rank_updates: bool = True,
    force: bool = False,
    convergence: Optional[int] = None,
    ensemble: Optional[int] = None,
) -> List[Dict[str, Any]]:
    """Runs ``scene`` once per combination of the values of its swept keys (the
    cartesian product, in order), in parallel (rayon, the GIL released): the rows of
    ``rollstack blocks sweep scene SCENE --set KEY=VALUES ... --json``.

    ``set`` maps a dotted numeric scene key (``contact.mu``, ``base.amplitude``,
    ``blocks.width``, ``blocks.0.x``, ``solver.dt``; docs/scenes.md) to its values: a
    list of numbers, one number, or the CLI's text (``"0.1:0.5:0.1"``, ``"2,4,8"``).
    The scene must come from TOML (a file, a dict, keywords or a built-in name). Raises
    ``ValueError`` for an unknown key or a combination the model refuses, before any
    run, and for runs over the time guard unless ``force=True`` (as
    :func:`sweep_frequency`; ``convergence`` and ``ensemble`` too, on the failure time);
    a run the solver stops has its message in its row's ``error``::

        blocks.sweep_scene(blocks.Scene.builtin("shaking"),
                           {"contact.mu": [0.1, 0.3], "base.amplitude": "0.1,0.2"})
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"sweep_scene needs a rollstack.blocks.Scene, got {type(scene).__name__}")
    texts = []
    for key, values in set.items():
        if isinstance(values, str):
            texts.append(f"{key}={values}")
        else:
            seq = [values] if isinstance(values, (int, float)) else list(values)
            texts.append(f"{key}=" + ",".join(repr(float(v)) for v in seq))
    return _rollstack.blocks_sweep_scene(
        scene._inner,
        texts,
        None if t_end is None else number("t_end", t_end),
        bool(stop_at_failure),
        optional_number("prox_constant", prox_constant),
        bool(explore_branches),
        bool(last_resort),
        bool(low_rank_updates),
        bool(force),
        *_judged(convergence, ensemble),
    )


#: The columns of :func:`fragility`'s result that are numbers (NaN for null).
_FRAGILITY_NUMBERS = ("level", "pga_g", "pgv", "overturned", "failed", "failure_time",
                      "t_final", "steps", "wall_time_s")


def fragility(
    scene: Scene,
    records: Union[str, "os.PathLike[str]", Sequence[Union[str, "os.PathLike[str]"]]],
    scales: Union[str, float, Sequence[float]],
    *,
    measure: str = "scale",
    t_end: Optional[float] = None,
    prox_constant: Optional[float] = None,
    explore_branches: bool = True,
    last_resort: bool = True,
    low_rank_updates: bool = True,
    force: bool = False,
) -> Dict[str, Any]:
    """Fragility curves from recorded ground motions (``rollstack blocks fragility``,
    docs/fragility.md): ``scene`` with its base's x motion replaced by every record at
    every level, in parallel (rayon, the GIL released), and lognormal curves
    P = Φ(ln(x/θ)/β) fitted by maximum likelihood to whether a block overturned and
    whether the stack failed, against PGA (g) and PGV.

    ``records`` is a directory (every ``*.AT2`` and ``*.csv`` in it, sorted by name) or a
    sequence of record files (in that order); ``scales`` the levels, numbers or the
    CLI's text (``"0.1:2:0.1"``): factors on each record (``measure="scale"``) or target
    PGAs in g (``measure="pga"``). The scene must come from TOML and give
    ``solver.dt``; each run lasts its record unless ``t_end`` is given.

    Returns a dict of one entry per run, in order (each record at each level): numpy
    float64 arrays ``level``, ``pga_g``, ``pgv``, ``overturned`` and ``failed`` (1.0 or
    0.0; NaN for a run that stopped on an error), ``failure_time`` (NaN: none),
    ``t_final``, ``steps``, ``wall_time_s``, and lists ``record``, ``failure_kind``,
    ``error`` (None where there is none); and ``fits``: the four curves (overturned,
    then failed, each against PGA then PGV) as dicts with the keys of ``fit.json``
    (``theta``, ``beta``, ``theta_band``, ``beta_band``, ... or ``no_fit``, the reason
    no curve fits). Bad records, levels or scenes raise ``ValueError`` before any run::

        study = blocks.fragility(blocks.Scene.from_toml("column.toml"), "quakes",
                                 "0.1:2:0.1", measure="pga")
        study["fits"][0]["theta"], study["pga_g"], study["overturned"]
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"fragility needs a rollstack.blocks.Scene, got {type(scene).__name__}")
    if isinstance(records, (str, os.PathLike)):
        paths = [os.fspath(records)]
    elif isinstance(records, Sequence) and all(isinstance(r, (str, os.PathLike)) for r in records):
        paths = [os.fspath(r) for r in records]
    else:
        raise TypeError("records must be a directory or a sequence of record files, got "
                        f"{type(records).__name__}")
    levels = scales if isinstance(scales, str) else np.asarray(scales, dtype=float).ravel().tolist()
    out = _rollstack.blocks_fragility(
        scene._inner, paths, levels, str(measure),
        optional_number("t_end", t_end), optional_number("prox_constant", prox_constant),
        bool(explore_branches), bool(last_resort), bool(low_rank_updates), bool(force),
    )
    rows = out["rows"]
    result: Dict[str, Any] = {
        key: np.array([math.nan if r[key] is None else float(r[key]) for r in rows],
                      dtype=float)
        for key in _FRAGILITY_NUMBERS
    }
    for key in ("record", "failure_kind", "error"):
        result[key] = [r[key] for r in rows]
    result["fits"] = out["fits"]
    return result


def explore(
    scene: Scene,
    *,
    t_end: Optional[float] = None,
    strategy: str = "breadth",
    max_branches: int = 1000,
    max_depth: Optional[int] = None,
    max_wall: Optional[float] = None,
    branch_rule: str = "self_consistent",
    probe_flips: bool = False,
    classify: bool = False,
    prox_constant: Optional[float] = None,
    force: bool = False,
) -> Dict[str, Any]:
    """Every continuation of ``scene``'s run (thesis §4.4, Figure 4.5): at a step with
    several solutions each becomes a branch, followed from the fork on (``rollstack
    blocks explore``). ``strategy`` is ``"breadth"`` (a generation at a time, in
    parallel) or ``"depth"``; ``max_branches``, ``max_depth`` and ``max_wall`` (seconds)
    cap the tree; ``branch_rule`` is ``"self_consistent"`` (solutions of the step's
    equations; also spelled ``"self-consistent"``, as on the command line) or ``"converged"`` (the thesis's count); ``probe_flips`` also looks for
    solutions Newton does not reveal (Painlevé's); ``classify`` labels each fork real,
    artefact or undecided, with its reason, from its candidates checked against the
    contact laws and a window of five steps taken again at Δt/2 and Δt/4 under both
    rules (docs/exploration.md). A root run estimated
    to take more than ten minutes is refused (ValueError) unless ``force``.

    Returns the JSON of ``rollstack blocks explore --json`` (branches, leaves, forks,
    labels, outcomes, ...) with ``branch_rows`` (the rows of branches.csv) and
    ``fork_rows`` (one dict per fork: contact states of each candidate, each
    candidate's contact-law check ``candidates``, and the ``evidence``). The
    tree does not depend on the number of threads."""
    if not isinstance(scene, Scene):
        raise TypeError(f"explore needs a rollstack.blocks.Scene, got {type(scene).__name__}")
    return _rollstack.blocks_explore(
        scene._inner,
        None if t_end is None else number("t_end", t_end),
        str(strategy),
        count("max_branches", max_branches),
        None if max_depth is None else count("max_depth", max_depth),
        None if max_wall is None else number("max_wall", max_wall),
        str(branch_rule),
        bool(probe_flips),
        bool(classify),
        optional_number("prox_constant", prox_constant),
        bool(force),
    )


def painleve(
    aspect: float, mu: float = 0.2, mu_max: float = 3.0, grid: int = 121
) -> Dict[str, Any]:
    """Painlevé's paradoxes for one block of aspect ratio w/h = ``aspect`` on a rough
    plane (App. I, ERRATA 18), as ``rollstack blocks painleve``.

    Returns a dict: ``report`` (the dict of ``rollstack blocks painleve --json``: the
    admissible angles ``theta_min``, ``theta_max`` (I.1.3), the least friction
    coefficient ``mu_min`` for which b of (I.1.8) can vanish (4/3) and where, per slip
    direction, and the line-contact LCP (I.2.10) solved for μ_d = ``mu``), and the
    b-sign grid of Figure I.2(b) (``painleve_b_grid.csv``): ``theta`` (grid,) rad,
    ``mu`` (grid,) from 0 to ``mu_max``, ``b_slip_positive`` and ``b_slip_negative``
    (grid, grid), row j at μ_d = ``mu[j]``, and ``admissible`` (grid,) bool.

    Raises ``ValueError`` naming the parameter for an aspect ≤ 0, a negative ``mu``, a
    ``mu_max`` ≤ 0, a ``grid`` under 2 or over 2000, NaN or a value of the wrong type.
    """
    return _rollstack.blocks_painleve(
        number("aspect", aspect), number("mu", mu), number("mu_max", mu_max), count("grid", grid)
    )


def work_precision(
    system: str = "block",
    dts: Sequence[float] = (1e-2, 5e-3, 2e-3, 1e-3, 5e-4),
    reference_factor: float = 16.0,
    repeat: int = 3,
    force: bool = False,
) -> Dict[str, Any]:
    """Speed against error for block stacks, as ``rollstack blocks work-precision``: each
    Δt of ``dts`` run by the nonsmooth generalized-α scheme and by Moreau-Jean, the error
    at the end time measured against a generalized-α run with Δt = min(dts) /
    ``reference_factor``, each point the fastest of ``repeat`` runs.

    ``system`` is ``"block"`` (one block sliding and rocking on a shaken base, to t = 2),
    ``"column"`` (three blocks, to t = 0.8) or ``"lire"`` (the Lire collapse before its
    first fork, to t = 5). Returns the dict of ``rollstack blocks work-precision --json``:
    ``rows`` (scheme, dt, error, penetration, wall_time_s, contact_events,
    follows_reference, fitted, error_message), ``orders`` (per scheme: ``status``
    ``"fitted"`` or ``"not_in_asymptotic_range"``, ``order``, ``dts``: an order is fitted
    only over the smallest Δt whose runs follow the reference's contact events),
    ``reference_dt``, ``reference_events``.

    Runs with the GIL released; Ctrl-C stops it before the next step and raises
    ``KeyboardInterrupt``. Raises ``ValueError`` naming the parameter for an unknown
    system, a Δt that is not positive and finite, a ``reference_factor`` under 1,
    ``repeat`` outside 1..1000, or a reference run estimated to take longer than ten
    minutes (the time guard of the command line; ``force=True`` runs it anyway);
    :class:`rollstack.SolverError` when the reference run fails.
    """
    if isinstance(dts, (str, bytes)) or not hasattr(dts, "__iter__"):
        raise ValueError(f"dts must be a sequence of numbers, got {dts!r}")
    return _rollstack.blocks_work_precision(
        str(system),
        [number(f"dts[{i}]", d) for i, d in enumerate(dts)],
        number("reference_factor", reference_factor),
        count("repeat", repeat),
        bool(force),
    )


def converge(
    scene: Union[Scene, str],
    *,
    levels: int = 2,
    ensemble: int = 2,
    t_end: Optional[float] = None,
    force: bool = False,
) -> Dict[str, Any]:
    """Whether ``scene``'s answer can be trusted, as ``rollstack blocks converge``: the
    scene (a :class:`Scene` or a built-in scene's name) run at Δt/2^k for k = 0…``levels``
    and, at the finest Δt, ``ensemble`` perturbed runs per magnitude (10⁻¹⁰, 10⁻⁷, 10⁻⁴;
    the blocks' initial x, or the base's frequency), with a verdict on the failure time
    and on the outcome: ``converged`` (with its tolerance and, over three levels, its
    observed order), ``chaotic`` (with the ensemble's spread, when nearby motions
    separate and a finite-time Lyapunov estimate), ``non_unique`` (a run forked) or
    ``not_converged`` (docs/exploration.md, "Convergence as an answer").

    Returns the dict of ``rollstack blocks converge --json`` without ``files`` and
    ``notes``: ``failure`` and ``outcome`` (the verdicts), ``separation``, ``runs`` (each
    run's failure time, outcome, final poses, forks and separation), ``dts``, ...

    Runs in parallel with the GIL released; Ctrl-C stops the runs within their current
    step and raises ``KeyboardInterrupt``. Raises ``ValueError`` naming the parameter for
    ``levels`` outside 1..8, ``ensemble`` outside 0..20, a ``t_end`` that is not positive,
    or runs estimated to take longer than ten minutes (the time guard of the command line;
    ``force=True`` runs them anyway, unwatched)."""
    if isinstance(scene, str):
        scene = Scene.builtin(scene)
    if not isinstance(scene, Scene):
        raise TypeError(
            "converge needs a rollstack.blocks.Scene or a built-in scene's name, "
            f"got {type(scene).__name__}"
        )
    return _rollstack.blocks_converge(
        scene._inner,
        count("levels", levels),
        count("ensemble", ensemble),
        None if t_end is None else number("t_end", t_end),
        bool(force),
    )
