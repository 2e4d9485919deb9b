"""rollstack: how constrained rigid bodies move when they roll, tip, slide and collide.

Python bindings of the rollstack Rust crates (T. E. Honein, *On the Dynamics of
Constrained Rigid Bodies*, PhD thesis, UC Berkeley, 2024). Every number comes from the
library functions the ``rollstack`` command line calls; reports equal the command line's
``--json`` output, trajectories are numpy arrays.

Submodules mirror the crates:

- :mod:`rollstack.rotations`: axis-angle, quaternions, matrices, the 12 Euler sets
  (§2.2, App. A), batched over leading axes;
- :mod:`rollstack.sphere`: the rolling sphere: rectangle holonomy (2.4.2)-(2.4.6), the
  planner (2.4.12), the Euler three-rectangle planner (§2.5), rolling (2.3.4)-(2.3.5);
- :mod:`rollstack.cylinders`: support statics (3.3.8)-(3.3.20) and the curves of
  Figures 3.3-3.8, the holonomy of §3.4, the Frobenius test (App. D, F), also on your
  own Pfaffian system, the transport of two cylinders (§3.6) and its sweeps (Figure 3.14,
  the slip onset under a push);
- :mod:`rollstack.nsga`: benchmark systems and work-precision runs (§4.2, App. H);
- :mod:`rollstack.blocks`: block stacks (Ch. 4, App. G-I): scenes, simulations,
  the Lire, shaking and sliding presets, sweeps, explorations of every motion,
  Painlevé's paradoxes (App. I) and the work-precision diagram of block stacks.

Angles are radians. Bad input raises ``ValueError`` with the library's message; a run
the solver stops raises :class:`SolverError` carrying the partial result.
"""

from ._rollstack import SolverError, __version__
from . import blocks, cylinders, nsga, rotations, sphere

__all__ = [
    "SolverError",
    "__version__",
    "blocks",
    "cylinders",
    "nsga",
    "rotations",
    "sphere",
]
