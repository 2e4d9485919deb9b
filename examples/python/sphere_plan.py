"""Every rectangle that reorients a rolling sphere by 3π/2 about (0.1, 0.99, 0.1)
(2.4.12), drawn as paths of the centre.

    python examples/python/sphere_plan.py [OUT_DIR]       # writes sphere_plan.png
"""

import math
import os
import sys

import matplotlib

if not os.environ.get("DISPLAY"):
    matplotlib.use("Agg")
import matplotlib.pyplot as plt

from rollstack import sphere

out_dir = sys.argv[1] if len(sys.argv) > 1 else "."
os.makedirs(out_dir, exist_ok=True)

plan = sphere.plan(3 * math.pi / 2, [0.1, 0.98994949, 0.1])
print(f"{len(plan['rectangles'])} rectangle(s), the shortest: no. {plan['shortest']}")

fig, ax = plt.subplots(figsize=(10, 4.5))
for i, rect in enumerate(plan["rectangles"]):
    xs, ys = zip(*rect["waypoints"])
    width = 2.5 if i == plan["shortest"] else 1.0
    ax.plot(xs, ys, linewidth=width, label=f"no. {i}, length {rect['path_length']:.3f}")
    ax.plot(xs[0], ys[0], "k.")
ax.set_aspect("equal")
ax.set_xlabel("E1 (units of R)")
ax.set_ylabel("E2 (units of R)")
ax.legend(fontsize="small", loc="upper left", bbox_to_anchor=(1.02, 1.0))
fig.tight_layout()
ax.set_title("Rectangles producing the rotation by 3π/2")
path = os.path.join(out_dir, "sphere_plan.png")
fig.savefig(path, dpi=100)
print("wrote", path)
