# Type stubs of the compiled module rollstack._rollstack (crates/python/src). The public
# API is the Python modules beside this file; these functions are their back end.
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

__version__: str

class SolverError(RuntimeError):
    result: Any

class Scene:
    @property
    def toml(self) -> Optional[str]: ...
    @property
    def title(self) -> str: ...
    @property
    def n_blocks(self) -> int: ...
    @property
    def warnings(self) -> List[str]: ...
    def report(self) -> Dict[str, Any]: ...

def blocks_scene_from_toml(text: str, title: str = ..., dir: str = ...) -> Scene: ...
def blocks_scene_from_json(text: str, title: str = ...) -> Scene: ...
def blocks_builtin_scene(name: str) -> Scene: ...
def blocks_read_record(
    path: str,
    dt: Optional[float] = ...,
    scale: float = ...,
    scale_to_pga: Optional[float] = ...,
    baseline: str = ...,
    unit: float = ...,
) -> Dict[str, Any]: ...
def blocks_pulse(
    shape: str, amplitude: float, period: float, t: List[float], start: float = ...
) -> Dict[str, Any]: ...
def blocks_builtin_scenes() -> List[Tuple[str, str]]: ...
def blocks_lire(blocks: int, perturb: str, floor: bool) -> Scene: ...
def blocks_shaking(
    blocks: int,
    omega: float,
    amplitude: float,
    mu: float,
    steps_per_period: float,
    periods: float,
    start_with_base: bool = ...,
) -> Scene: ...
def blocks_sliding(blocks: int, v0: float, t_end: float, mu: float) -> Scene: ...
def blocks_simulate(
    scene: Scene,
    t_end: Optional[float] = ...,
    prox_constant: Optional[float] = ...,
    explore_branches: bool = ...,
    last_resort: bool = ...,
    stop_at_failure: bool = ...,
    low_rank_updates: bool = ...,
    force: bool = ...,
) -> Dict[str, Any]: ...
def blocks_sweep_frequency(
    omegas: Sequence[float],
    periods: float,
    amplitude: float,
    blocks: int,
    steps_per_period: float,
    mu: float,
    prox_constant: Optional[float] = ...,
    explore_branches: bool = ...,
    last_resort: bool = ...,
    t_max: Optional[float] = ...,
    low_rank_updates: bool = ...,
    branches: int = ...,
    branch_rule: str = ...,
    force: bool = ...,
    convergence: Optional[int] = ...,
    ensemble: Optional[int] = ...,
) -> List[Dict[str, Any]]: ...
def blocks_explore(
    scene: Any,
    t_end: Optional[float] = ...,
    strategy: str = ...,
    max_branches: int = ...,
    max_depth: Optional[int] = ...,
    max_wall: Optional[float] = ...,
    branch_rule: str = ...,
    probe_flips: bool = ...,
    classify: bool = ...,
    prox_constant: Optional[float] = ...,
    force: bool = ...,
) -> Dict[str, Any]: ...
def blocks_sweep_slide(
    speeds: Sequence[float],
    t_end: float,
    blocks: int,
    mu: float,
    prox_constant: Optional[float] = ...,
    explore_branches: bool = ...,
    last_resort: bool = ...,
    low_rank_updates: bool = ...,
    branches: int = ...,
    branch_rule: str = ...,
    force: bool = ...,
    convergence: Optional[int] = ...,
    ensemble: Optional[int] = ...,
) -> List[Dict[str, Any]]: ...
def blocks_sweep_scene(
    scene: Scene,
    overrides: Sequence[str],
    t_end: Optional[float] = ...,
    stop_at_failure: bool = ...,
    prox_constant: Optional[float] = ...,
    explore_branches: bool = ...,
    last_resort: bool = ...,
    low_rank_updates: bool = ...,
    force: bool = ...,
    convergence: Optional[int] = ...,
    ensemble: Optional[int] = ...,
) -> List[Dict[str, Any]]: ...
def blocks_fragility(
    scene: Scene,
    records: Sequence[str],
    levels: Union[str, Sequence[float]],
    measure: str,
    t_end: Optional[float],
    prox_constant: Optional[float],
    explore_branches: bool,
    last_resort: bool,
    low_rank_updates: bool,
    force: bool,
) -> Dict[str, Any]: ...
def blocks_painleve(
    aspect: float, mu: float = ..., mu_max: float = ..., grid: int = ...
) -> Dict[str, Any]: ...
def blocks_converge(
    scene: Any,
    levels: int = ...,
    ensemble: int = ...,
    t_end: Optional[float] = ...,
    force: bool = ...,
) -> Dict[str, Any]: ...
def blocks_work_precision(
    system: str = ...,
    dts: Sequence[float] = ...,
    reference_factor: float = ...,
    repeat: int = ...,
    force: bool = ...,
) -> Dict[str, Any]: ...
def sphere_holonomy(theta: float, phi1: float, phi2: float, cw: bool = ...) -> Dict[str, Any]: ...
def sphere_plan(angle: float, axis: Sequence[float]) -> Dict[str, Any]: ...
def sphere_euler_plan(set: str, angles: Sequence[float]) -> Dict[str, Any]: ...
def sphere_roll(
    theta: Optional[float] = ...,
    phi1: Optional[float] = ...,
    phi2: Optional[float] = ...,
    cw: bool = ...,
    circle: Optional[float] = ...,
    polygon: Optional[Sequence[Sequence[float]]] = ...,
    steps: int = ...,
    integrator: str = ...,
) -> Dict[str, Any]: ...
def rotations_convert(values: np.ndarray, from_: str, to: str) -> np.ndarray: ...
def rotations_report(values: Sequence[float], from_: str) -> Dict[str, Any]: ...
def rotations_euler_sets() -> List[str]: ...
def cylinders_support(
    theta: float, r_over_h: float = ..., mu: float = ..., mass: Optional[float] = ..., gravity: float = ...
) -> Dict[str, Any]: ...
def cylinders_statics(r_over_h: float = ..., mu: float = ..., points: int = ...) -> Dict[str, Any]: ...
def cylinders_pair(
    theta: float, dt: float = ..., steps: int = ..., spin: float = ..., ramp: Optional[float] = ...,
    mu_floor: float = ..., mu_mutual: float = ..., push_over_mg: float = ..., rho_inf: float = ...,
    force: bool = ...
) -> Dict[str, Any]: ...
def cylinders_sweep_pair(
    theta: Union[str, float, Sequence[float]], dt: float = ..., steps: int = ..., spin: float = ...,
    force: bool = ...
) -> List[Dict[str, Any]]: ...
def cylinders_sweep_push(
    theta: Union[str, float, Sequence[float]], push: Union[str, float, Sequence[float]],
    mu_floor: float = ..., dt: float = ..., steps: int = ..., force: bool = ...
) -> List[Dict[str, Any]]: ...
def cylinders_frobenius(
    system: str = ..., config: str = ..., theta: float = ..., heading: float = ...,
    contact_at: Optional[float] = ..., r: float = ..., h: float = ...
) -> Dict[str, Any]: ...
def cylinders_frobenius_callable(
    function: Callable[[List[float]], Any], q: Sequence[float], step: float = ...
) -> Dict[str, Any]: ...
def nsga_ball(
    case: int, dt: float = ..., scheme: str = ..., rho_inf: float = ..., prox_constant: Optional[float] = ...
) -> Dict[str, Any]: ...
def nsga_work_precision(
    system: str, dts: Sequence[float] = ..., rho_inf: Sequence[float] = ..., repeat: int = ...
) -> Dict[str, Any]: ...
def cylinders_work_precision(
    theta: float = ..., dts: Sequence[float] = ..., reference_factor: float = ...,
    repeat: int = ..., force: bool = ...
) -> Dict[str, Any]: ...
def cylinders_holonomy_rectangle(
    theta: float, phi1: float, phi2: float, s: float = ..., case: str = ..., cw: bool = ...,
    psi0: float = ..., r_over_h: float = ..., max_step: float = ...
) -> Dict[str, Any]: ...
def cylinders_holonomy_circle(
    ell: float, theta: float, h: Optional[float] = ..., r_over_h: Optional[float] = ...,
    r: float = ..., case: str = ..., cw: bool = ..., max_step: float = ...
) -> Dict[str, Any]: ...
