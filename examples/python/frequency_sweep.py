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
# Every ω is watched for 40 time units (a fixed number of periods would watch a fast
# base for less time than a slow one).
rows = blocks.sweep_frequency(omegas, t_max=40.0)
failed = [(r["omega"], r["inv_failure_time"]) for r in rows if r["outcome"] == "failed"]
survived = [r["omega"] for r in rows if r["outcome"] == "no_failure_by_horizon"]
for r in rows:
    print(f"omega = {r['omega']:5.1f}  {r['outcome']}  failure_time = {r['failure_time']}  error = {r['error']}")

fig, ax = plt.subplots(figsize=(7, 4))
if failed:
    ax.plot(*zip(*failed), "o", label="1/T, T: first loss of support")
if survived:
    ax.plot(survived, [0.0] * len(survived), "^", label="no failure by t = 40, drawn at 1/T = 0")
ax.legend()
ax.set_xlabel("ω (rad per time unit)")
ax.set_ylabel("1 / failure time")
ax.set_title("Shaken column of 4 blocks, A = 0.2, t ≤ 40 (Figure 4.6)")
path = os.path.join(out_dir, "frequency_sweep.png")
fig.savefig(path, dpi=100)
print("wrote", path)
