#!/usr/bin/env python3
"""The solver's reference workload, measured with one binary's variants or several binaries.

    scripts/reference_workload.py [--repeat N] [--only NAME,...] BIN [--variant "NAME=VALUE ..."]...
    scripts/reference_workload.py [--repeat N] [--only NAME,...] BIN [BIN ...]

The workload every change of the step's policy or of a tuning constant is judged on
(docs/tuning.md): the 135-run shaken-column matrix, the Lire collapse and its
landing on a floor, a 30-block column kicked by its moving base, and the cylinder pair.

To measure a constant or a stage, give one binary and a variant per value: each variant
is one or more `NAME=VALUE` assignments of nsga's options (separated by spaces), passed
to every command as the hidden `--tuning NAME=VALUE` flag (`nsga::Options::set`):
`--variant tuning.stall_iterations=4`, `--variant policy.max_halvings=0`,
`--variant "policy.branch_trials=false policy.max_halvings=0"`. Or give
several binaries (a change that is not an option). The runs alternate between the
configurations, the first (the binary as it is) being the reference; the table gives,
per workload and configuration, the machine-independent work (linear solves, failed
steps, last-resort steps, unresolved runs: those a step nothing resolved ended), the
solver time per step (median over the repeats, with its range), and the ratios of the
linear solves and of the median time to the reference's.

Counts are deterministic; times are not (a shared machine is noisy: quote medians and
ratios, and judge on the counts first). Needs only Python 3 and the binaries; writes
its sweep directories under a temporary directory that it removes.
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


def run(config, name, tmp, repeat):
    """One run of workload `name`: (counts, solver seconds, worst µs per step, and for the
    matrix its per-run figures, `per_row`)."""
    binary, tuning = config["binary"], config["tuning"]
    args = list(WORKLOADS[name])
    if name == "matrix":
        # A directory of its own for each run: a sweep run again into the same --out
        # resumes from its row log and would report the first run's rows and times.
        args += ["--out", f"{tmp}/{name}-{config['index']}-{repeat}"]
    for assignment in tuning:
        args += ["--tuning", assignment]
    out = subprocess.run([binary, *args], capture_output=True, text=True, check=False)
    try:
        report = json.loads(out.stdout)
    except json.JSONDecodeError:
        report = None
    if report is None or out.returncode not in (0, 3):
        # A run that a step nothing resolves ends without its report (the cylinder pair):
        # one unresolved run, no counts.
        if tuning and "--tuning:" not in out.stderr:
            print(f"{name} {config['label']}: {out.stderr.strip()}", file=sys.stderr)
            return {"runs": 1, "unresolved": 1}, 0.0, 0.0, None
        sys.exit(f"{binary} {' '.join(args)}: exit {out.returncode}\n{out.stderr}")
    rows = report["rows"] if name == "matrix" else [report]
    def total(key):
        # "–" where the command does not report the count (the cylinder pair's JSON has
        # Newton iterations, not linear solves or failed steps).
        if not any(key in r for r in rows):
            return "–"
        return sum((r.get(key) or 0) for r in rows)
    counts = {
        "runs": len(rows),
        "unresolved": sum(1 for r in rows if r.get("error")),
        "linear_solves": total("linear_solves"),
        "failed_steps": total("failed_steps"),
        "fallback_steps": total("fallback_steps"),
        "steps": total("steps"),
        "newton_iterations": total("newton_iterations"),
    }
    seconds = [r.get("wall_time_s") or 0.0 for r in rows]
    worst = max((s / r["steps"] for s, r in zip(seconds, rows) if r.get("steps")), default=0.0)
    return counts, sum(seconds), worst, per_row(rows) if name == "matrix" else None


def per_row(rows):
    """The matrix's figures as issue 62 states its targets: the mean over the runs of each
    run's µs per step, and the median of those by number of blocks n."""
    us, by_n = [], {}
    for r in rows:
        if not r.get("steps"):
            continue
        v = 1e6 * (r.get("wall_time_s") or 0.0) / r["steps"]
        us.append(v)
        n = next(int(s["value"]) for s in r["set"] if s["key"] == "blocks.count")
        by_n.setdefault(n, []).append(v)
    return {"row_mean": statistics.mean(us) if us else 0.0,
            "by_n": {n: statistics.median(v) for n, v in sorted(by_n.items())}}


def configurations(binaries, variants):
    """The binaries as they are, then the first binary with each variant."""
    configs = [{"binary": b, "tuning": [], "label": b} for b in binaries]
    configs += [{"binary": binaries[0], "tuning": v.split(), "label": v} for v in variants]
    for i, c in enumerate(configs):
        c["index"] = i
    return configs


def ratio(value, reference):
    """value / reference as text, "–" where either is not a positive number."""
    if not (isinstance(value, (int, float)) and isinstance(reference, (int, float))) or reference <= 0:
        return "–"
    return f"{value / reference:.3f}"


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("binaries", nargs="+", metavar="BIN")
    p.add_argument("--variant", action="append", default=[], metavar="'NAME=VALUE ...'",
                   help="run the first binary with these --tuning assignments too (repeatable)")
    p.add_argument("--repeat", type=int, default=3, help="runs per workload and configuration (3)")
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
    for v in a.variant:
        if not v.split() or any("=" not in x for x in v.split()):
            p.error(f"--variant {v!r}: expected NAME=VALUE assignments separated by spaces")
    configs = configurations(a.binaries, a.variant)
    table = []
    with tempfile.TemporaryDirectory() as tmp:
        for name in names:
            results = [[] for _ in configs]
            for i in range(a.repeat):
                for c in configs:
                    results[c["index"]].append(run(c, name, tmp, i))
                    print(f"{name}: {c['label']} run {i + 1}/{a.repeat}", file=sys.stderr)
            reference = None
            for c, rs in zip(configs, results):
                counts = rs[0][0]
                if any(r[0] != counts for r in rs):
                    print(f"warning: {name} with {c['label']}: counts differ between repeats",
                          file=sys.stderr)
                steps = counts.get("steps") if isinstance(counts.get("steps"), int) else 1
                us = [1e6 * r[1] / max(steps, 1) for r in rs]
                row = {"workload": name, "config": c["label"], **counts,
                       "us_per_step_median": statistics.median(us),
                       "us_per_step_min": min(us), "us_per_step_max": max(us),
                       "worst_run_us_per_step": statistics.median(1e6 * r[2] for r in rs)}
                if rs[0][3] is not None:
                    # Medians over the repeats of the per-run figures.
                    row["row_mean_us_per_step"] = statistics.median(r[3]["row_mean"] for r in rs)
                    row["median_us_per_step_by_n"] = {
                        n: statistics.median(r[3]["by_n"][n] for r in rs) for n in rs[0][3]["by_n"]}
                reference = reference or row
                row["solves_ratio"] = ratio(row.get("linear_solves"), reference.get("linear_solves"))
                row["time_ratio"] = ratio(row["us_per_step_median"], reference["us_per_step_median"])
                table.append(row)
    if a.json:
        print(json.dumps(table, indent=1))
        return
    head = ("workload", "configuration", "runs", "unresolved", "linear_solves", "failed_steps",
            "last-resort steps", "steps", "newton_iterations", "µs/step median (range)",
            "worst run µs/step", "solves ratio", "time ratio")
    print(" | ".join(head))
    for r in table:
        print(" | ".join(str(x) for x in (
            r["workload"], r["config"], r["runs"], r["unresolved"], r.get("linear_solves", "–"),
            r.get("failed_steps", "–"), r.get("fallback_steps", "–"), r.get("steps", "–"),
            r.get("newton_iterations", "–"),
            f"{r['us_per_step_median']:.1f} ({r['us_per_step_min']:.1f}–{r['us_per_step_max']:.1f})",
            f"{r['worst_run_us_per_step']:.0f}", r["solves_ratio"], r["time_ratio"])))
    for r in table:
        by_n = r.get("median_us_per_step_by_n")
        if by_n:
            ns = sorted(by_n)
            print(f"{r['workload']} {r['config']}: mean over the runs "
                  f"{r['row_mean_us_per_step']:.1f} µs/step; median by n: "
                  + ", ".join(f"{n}: {by_n[n]:.1f}" for n in ns)
                  + f"; n = {ns[-1]} / n = {ns[0]}: {by_n[ns[-1]] / by_n[ns[0]]:.1f}")


if __name__ == "__main__":
    main()
