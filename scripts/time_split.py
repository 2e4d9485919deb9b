#!/usr/bin/env python3
"""Where the shaken-column matrix's solver time goes, by kind of work and by n.

    scripts/time_split.py BIN

Runs the 135 rows of the reference workload's matrix (scripts/reference_workload.py) one
by one as `BIN blocks shake --json` and sums their `newton_work`: per step, the
evaluations, exact (Jacobian and factorization), simplified and low-rank updates and
line-search trials, and the seconds of each kind of work (`newton_work.seconds`), the
rest of the solver time being `other` (the policy, the prediction, the broad phase,
commits). Prints one line for the whole matrix and one per block count, and the cost
of one evaluation, one exact update and one simplified update. Counts are exact;
seconds are those of the machine (quote ratios). Takes about a minute on 2 cores.
"""
import collections
import itertools
import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from reference_workload import MATRIX  # noqa: E402  (the harness's matrix, one source)


def matrix_values():
    """The values of each `--set KEY=VALUES` of the harness's matrix (`a:b:step` or a
    comma list), and its `--t-end`."""
    values = {}
    for flag, value in zip(MATRIX, MATRIX[1:]):
        if flag == "--set":
            key, spec = value.split("=")
            if ":" in spec:
                first, last, step = (int(v) for v in spec.split(":"))
                values[key] = list(range(first, last + 1, step))
            else:
                values[key] = spec.split(",")
    return values, MATRIX[MATRIX.index("--t-end") + 1]


def row(binary, n, omega, mu, solver, out):
    """One row's counts and seconds: the matrix's row as one `blocks shake` run, with the
    matrix's `solver` flags (steps per period, t_end)."""
    args = [binary, "blocks", "shake", "--blocks", str(n), "--omega", str(omega),
            "--mu", str(mu), "--amplitude", "0.2", *solver,
            "--json", "--force", "--max-frames", "0", "--out", out]
    run = json.loads(subprocess.run(args, capture_output=True, text=True, check=True).stdout)
    work = run["newton_work"]
    c = collections.Counter({
        "wall": run["wall_time_s"], "steps": run["steps"],
        "evaluations": work["evaluations"], "exact": work["exact_updates"],
        "kept": work["kept_updates"], "low_rank": work["low_rank_updates"],
        "line_search": work["line_search_trials"],
    })
    for kind, seconds in work["seconds"].items():
        c["s_" + kind] = seconds
    return c


def show(name, c):
    steps = c["steps"]
    per_step = {k[2:]: c[k] / steps * 1e6 for k in sorted(c) if k.startswith("s_")}
    other = c["wall"] / steps * 1e6 - sum(per_step.values())
    counts = " ".join(f"{k} {c[k] / steps:.3f}" for k in
                      ["evaluations", "exact", "kept", "low_rank", "line_search"])
    times = " ".join(f"{k} {v:.1f}" for k, v in per_step.items())
    print(f"{name}: {c['wall'] / steps * 1e6:.1f} µs per step; per step: {counts}; "
          f"µs per step: {times} other {other:.1f}")
    simplified = max(c["kept"] + c["low_rank"], 1)
    exact = max(c["exact"], 1)
    print(f"    µs each: evaluation {c['s_evaluation'] / c['evaluations'] * 1e6:.2f}, "
          f"exact update {c['s_jacobian'] / exact * 1e6:.1f} (Jacobian) + "
          f"{c['s_factorization'] / exact * 1e6:.1f} (factorization), "
          f"simplified update {c['s_simplified'] / simplified * 1e6:.2f}")


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    binary = sys.argv[1]
    values, t_end = matrix_values()
    solver = ["--steps-per-period", values["solver.steps_per_period"][0], "--t-end", t_end]
    blocks = values["blocks.count"]
    total, by_n = collections.Counter(), collections.defaultdict(collections.Counter)
    with tempfile.TemporaryDirectory() as out:
        for n, omega, mu in itertools.product(
            blocks, values["base.omega"], values["contact.mu"]
        ):
            c = row(binary, n, omega, mu, solver, out)
            total.update(c)
            by_n[n].update(c)
    show("matrix", total)
    for n in blocks:
        show(f"n = {n}", by_n[n])


if __name__ == "__main__":
    main()
