#!/usr/bin/env python3
"""The solver's reference workload, measured with one or more `rollstack` binaries.

    scripts/reference_workload.py [--repeat N] [--only NAME,...] BIN [BIN ...]

The workload every change of the step's policy or of a tuning constant is judged on
(docs/method.md §8): the 135-run shaken-column matrix, the Lire collapse and its landing
on a floor, a 30-block column kicked by its moving base, and the cylinder pair. To
measure a constant's effect, build the binary twice (with the constant's two values,
`cargo build --release -p rollstack` and a copy of target/release/rollstack), then pass
both binaries: the runs alternate between them, and the table gives, per workload and
binary, the machine-independent work (linear solves, failed steps, last-resort steps)
and the solver time (median over the repeats, with its range).

Counts are deterministic; times are not (a shared machine is noisy: quote medians and
ratios). Needs only Python 3 and the binaries; writes its sweep directories under a
temporary directory that it removes.
"""
import argparse
import json
import statistics
import subprocess
import sys
import tempfile

MATRIX = [
    "blocks", "sweep", "scene", "shaking",
    "--set", "blocks.count=2:6:1",
    "--set", "base.omega=2,4,8,12,16,20,24,32,40",
    "--set", "contact.mu=0.2,0.3,0.5",
    "--set", "solver.steps_per_period=200",
    "--t-end", "20", "--json", "--force",
]

WORKLOADS = {
    "matrix": MATRIX,
    "lire_collapse": ["blocks", "lire", "--perturb", "bottom", "--json"],
    "lire_floor": ["blocks", "lire", "--perturb", "bottom", "--floor", "--json"],
    "kicked30": ["blocks", "shake", "--blocks", "30", "--omega", "2", "--amplitude", "0.001",
                 "--mu", "0.2", "--steps-per-period", "314", "--t-end", "1", "--json", "--force"],
    "cylinder_pair": ["cylinder", "pair", "--theta", "30deg", "--json"],
}


def run(binary, name, tmp, repeat):
    """One run of workload `name`: (counts, solver seconds, worst µs per step)."""
    args = list(WORKLOADS[name])
    if name == "matrix":
        # A directory of its own for each run: a sweep run again into the same --out
        # resumes from its row log and would report the first run's rows and times.
        args += ["--out", f"{tmp}/{name}-{abs(hash(binary))}-{repeat}"]
    out = subprocess.run([binary, *args], capture_output=True, text=True, check=False)
    if out.returncode not in (0, 3):
        sys.exit(f"{binary} {' '.join(args)}: exit {out.returncode}\n{out.stderr}")
    report = json.loads(out.stdout)
    rows = report["rows"] if name == "matrix" else [report]
    def total(key):
        # "–" where the command does not report the count (the cylinder pair's JSON has
        # Newton iterations, not linear solves or failed steps).
        if not any(key in r for r in rows):
            return "–"
        return sum((r.get(key) or 0) for r in rows)
    counts = {
        "runs": len(rows),
        "errors": sum(1 for r in rows if r.get("error")),
        "linear_solves": total("linear_solves"),
        "failed_steps": total("failed_steps"),
        "fallback_steps": total("fallback_steps"),
        "steps": total("steps"),
        "newton_iterations": total("newton_iterations"),
    }
    seconds = [r.get("wall_time_s") or 0.0 for r in rows]
    worst = max((s / r["steps"] for s, r in zip(seconds, rows) if r.get("steps")), default=0.0)
    return counts, sum(seconds), worst


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("binaries", nargs="+", metavar="BIN")
    p.add_argument("--repeat", type=int, default=3, help="runs per workload and binary (3)")
    p.add_argument("--only", default=",".join(WORKLOADS),
                   help=f"comma list of workloads (default all: {','.join(WORKLOADS)})")
    p.add_argument("--json", action="store_true", help="print the table as JSON")
    a = p.parse_args()
    names = a.only.split(",")
    for n in names:
        if n not in WORKLOADS:
            p.error(f"--only: unknown workload {n!r}; the workloads are {', '.join(WORKLOADS)}")
    if a.repeat < 1:
        p.error("--repeat must be at least 1")
    table = []
    with tempfile.TemporaryDirectory() as tmp:
        for name in names:
            results = {b: [] for b in a.binaries}
            for i in range(a.repeat):
                for b in a.binaries:
                    results[b].append(run(b, name, tmp, i))
                    print(f"{name}: {b} run {i + 1}/{a.repeat}", file=sys.stderr)
            for b, rs in results.items():
                counts = rs[0][0]
                if any(r[0] != counts for r in rs):
                    print(f"warning: {name} with {b}: counts differ between repeats", file=sys.stderr)
                steps = counts["steps"] if isinstance(counts["steps"], int) else 1
                us = [1e6 * r[1] / max(steps, 1) for r in rs]
                table.append({"workload": name, "binary": b, **counts,
                              "us_per_step_median": statistics.median(us),
                              "us_per_step_min": min(us), "us_per_step_max": max(us),
                              "worst_run_us_per_step": statistics.median(1e6 * r[2] for r in rs)})
    if a.json:
        print(json.dumps(table, indent=1))
        return
    head = ("workload", "binary", "runs", "errors", "linear_solves", "failed_steps",
            "fallback_steps", "steps", "newton_iterations", "µs/step median (range)",
            "worst run µs/step")
    print(" | ".join(head))
    for r in table:
        print(" | ".join(str(x) for x in (
            r["workload"], r["binary"], r["runs"], r["errors"], r["linear_solves"],
            r["failed_steps"], r["fallback_steps"], r["steps"], r["newton_iterations"],
            f"{r['us_per_step_median']:.1f} ({r['us_per_step_min']:.1f}–{r['us_per_step_max']:.1f})",
            f"{r['worst_run_us_per_step']:.0f}")))


if __name__ == "__main__":
    main()
