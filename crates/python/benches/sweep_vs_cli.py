"""Times a 100-point frequency sweep (Figure 4.6, ω = 0.2, 0.4, ..., 20) from Python
and from the command line, best of REPEAT runs each.

    python crates/python/benches/sweep_vs_cli.py PATH/TO/rollstack [REPEAT]

Build the binary with the module's profile for a like-for-like comparison:
`cargo build -p rollstack --profile python` (target/python/rollstack).
"""

import subprocess
import sys
import time

from rollstack import blocks

cli = sys.argv[1]
repeat = int(sys.argv[2]) if len(sys.argv) > 2 else 3
omegas = [round(0.2 * k, 10) for k in range(1, 101)]


def best(f):
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        f()
        times.append(time.perf_counter() - start)
    return min(times)


py = best(lambda: blocks.sweep_frequency(omegas))
sh = best(lambda: subprocess.run([cli, "blocks", "sweep", "frequency", "--omega", "0.2:20:0.2", "--json"],
                                 check=True, capture_output=True))
print(f"100-point frequency sweep: Python {py:.3f} s, CLI {sh:.3f} s, ratio {py / sh:.3f}")
