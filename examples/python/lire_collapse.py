"""The Leaning Tower of Lire collapses (§4.3, Figure 4.4): the bottom block perturbed by
0.01, the block angles and the events of the run.

    python examples/python/lire_collapse.py [OUT_DIR]     # writes lire_collapse.png
"""

import os
import sys

import matplotlib

if not os.environ.get("DISPLAY"):
    matplotlib.use("Agg")
import matplotlib.pyplot as plt

from rollstack import blocks

out_dir = sys.argv[1] if len(sys.argv) > 1 else "."
os.makedirs(out_dir, exist_ok=True)

result = blocks.simulate(blocks.lire(perturb="bottom"), t_end=10.0)
print(result)

fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
for k in range(result.q.shape[1]):
    top.plot(result.t, result.q[:, k, 2], label=f"block {k + 1}")
top.set_ylabel("θ (rad)")
top.legend(loc="upper left")
for k in range(result.q.shape[1]):
    bottom.plot(result.t, result.forces[:, k, 0] + result.forces[:, k, 1], label=f"interface {k + 1}")
bottom.set_ylabel("normal force")
bottom.set_xlabel("t")
for e in result.events:
    if e["kind"] in ("failure", "opening"):
        for ax in (top, bottom):
            ax.axvline(e["t"], color="grey", linestyle=":")
fig.suptitle("Leaning Tower of Lire, bottom block perturbed")
path = os.path.join(out_dir, "lire_collapse.png")
fig.savefig(path, dpi=100)
print("wrote", path)
