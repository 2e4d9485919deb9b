"""Failure time of a shaken column against the frequency (Figure 4.6), computed in
parallel by rollstack.blocks.sweep_frequency.

    python examples/python/frequency_sweep.py [OUT_DIR]   # writes frequency_sweep.png
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

omegas = [2.0 + 2.0 * i for i in range(10)]
rows = blocks.sweep_frequency(omegas)  # 10 base periods each, as the CLI
failed = [(r["omega"], r["inv_failure_time"]) for r in rows if r["inv_failure_time"] is not None]
for r in rows:
    print(f"omega = {r['omega']:5.1f}  failure_time = {r['failure_time']}  error = {r['error']}")

fig, ax = plt.subplots(figsize=(7, 4))
if failed:
    ax.plot(*zip(*failed), "o-")
ax.set_xlabel("ω (rad per time unit)")
ax.set_ylabel("1 / failure time")
ax.set_title("Shaken column of 4 blocks, A = 0.2 (Figure 4.6)")
path = os.path.join(out_dir, "frequency_sweep.png")
fig.savefig(path, dpi=100)
print("wrote", path)
