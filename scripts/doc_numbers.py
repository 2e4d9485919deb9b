#!/usr/bin/env python3
"""The numbers the docs quote from rollstack's runs, written by running it.

    scripts/doc_numbers.py BIN                 # rewrites every marked number in the docs
    scripts/doc_numbers.py BIN --check         # exit 1, with a diff, where a doc differs
    scripts/doc_numbers.py BIN --only NAME,... # only these entries

BIN is a release build (cargo build --release -p rollstack; target/release/rollstack).
Each entry of NUMBERS names a doc file, a marker NAME (the doc holds the text between
`<!-- NAME: begin -->` and `<!-- NAME: end -->`), what it runs and how it writes the
result. The reference workload's commands are those of scripts/reference_workload.py,
imported, so that the harness and the docs run the same thing. Counts (linear solves,
failed steps, failure times) are exact and the same on every machine; no timing is
written or checked here. The matrix takes a few minutes on 2 cores; the rest seconds (the 10 000-block
column about 15).

The cheap counts (the Lire collapse, its floor landing, the kicked 30-block column) are
also checked on every `cargo test` by crates/cli/tests/doc_numbers.rs with the debug
build, against the text this script writes. Numbers that record what a change saved
("N instead of M") are historical measurements, labelled as such in the docs, and are
not rewritten.
"""
import argparse
import csv
import difflib
import functools
import json
import os
import re
import subprocess
import sys
import tempfile
import textwrap

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import reference_workload  # noqa: E402  (the workload's commands, single-sourced)

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def grouped(n):
    """369344 → '369 344' (groups of three from 10 000 on, as the docs write counts)."""
    return f"{n:,}".replace(",", " ") if n >= 10_000 else str(n)


class Runner:
    """Runs BIN, each command once per script run (entries share the matrix)."""

    def __init__(self, binary, tmp):
        self.binary = binary
        self.tmp = tmp

    @functools.lru_cache(maxsize=None)
    def workload(self, name):
        """The counts of one reference workload (scripts/reference_workload.py)."""
        config = {"binary": self.binary, "tuning": [], "index": 0, "label": "docs"}
        counts = reference_workload.run(config, name, self.tmp, 0)[0]
        return counts

    def json(self, *args):
        out = subprocess.run([self.binary, *args], capture_output=True, text=True, check=False)
        if out.returncode not in (0, 3):
            sys.exit(f"{self.binary} {' '.join(args)}: exit {out.returncode}\n{out.stderr}")
        return json.loads(out.stdout)


def last_resort(n, where="anywhere"):
    return f"no unresolved or last-resort step {where}" if n == 0 else f"{n} last-resort steps"


def reference_counts(r):
    """method.md §8.3: the reference of "The stages measured"."""
    m, lire, floor, kicked = (r.workload(n) for n in ("matrix", "lire_collapse", "lire_floor", "kicked30"))
    fallback = sum(c["fallback_steps"] + c["unresolved"] for c in (m, lire, floor, kicked))
    return (
        f"matrix {grouped(m['linear_solves'])} linear solves, {m['failed_steps']} failed\n"
        f"steps; Lire collapse {lire['linear_solves']}; on a floor {floor['linear_solves']}; "
        f"kicked 30-block column {kicked['linear_solves']}; {last_resort(fallback)}"
    )


def matrix_counts(r):
    """tuning.md, "The workloads": the matrix as the binary runs it now."""
    m = r.workload("matrix")
    last = "no last-resort step" if m["fallback_steps"] == 0 else f"{m['fallback_steps']} last-resort steps"
    reach = "every run reaches t = 20" if m["unresolved"] == 0 else f"{m['unresolved']} runs stop before t = 20"
    return (
        f"{grouped(m['linear_solves'])} linear solves and {m['failed_steps']} failed steps, {last},\n"
        f"and {reach}"
    )


def lire_convergence(r):
    """exploration.md, "Convergence as an answer": the Lire collapse's failure times at
    Δt, Δt/2 and Δt/4 and the verdict (`blocks converge`, no ensemble)."""
    d = r.json("blocks", "converge", "lire-collapse", "--levels", "2", "--ensemble", "0",
               "--t-end", "7", "--json")
    times = [f"{run['failure_time']:.3f}" for run in d["runs"] if run["kind"] == "level"]
    return (
        f"fails at\n{times[0]}, {times[1]} and {times[2]} at Δt = 0.01, Δt/2 and Δt/4 "
        f"({d['failure']['verdict']}"
    )


def sci(x):
    """x as 1.3·10⁻¹³ (0 as 0)."""
    if x == 0:
        return "0"
    mantissa, exponent = f"{x:.1e}".split("e")
    sup = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")
    return f"{mantissa}·10{str(int(exponent)).translate(sup)}"


def parting(held_dir, solved_dir, apart=1e-9):
    """The first time at which two runs' trajectories (trajectory.csv in their --out
    directories) differ by more than `apart` in a pose, with their largest difference
    before it; None where they never do."""
    def rows(d):
        with open(os.path.join(d, "trajectory.csv")) as f:
            return list(csv.DictReader(f))
    before = 0.0
    for p, q in zip(rows(held_dir), rows(solved_dir)):
        poses = [k for k in p if k[:1] in ("x", "y") or k.startswith("theta")]
        d = max(abs(float(p[k]) - float(q[k])) for k in poses)
        if d > apart:
            return p["t"], before
        before = max(before, d)
    return None


def rest_counts(r):
    """method.md §8.2, "At rest": runs held at rest against the same runs solving every
    step (`--tuning policy.rest=false`)."""
    def pair(name, *args):
        dirs = [os.path.join(r.tmp, f"{name}-{run}") for run in ("held", "solved")]
        out = [[] if args[1] == "lire" else ["--force", "--out", d] for d in dirs]
        held = r.json(*args, *out[0], "--json")
        solved = r.json(*args, *out[1], "--json", "--tuning", "policy.rest=false")
        apart = max(abs(p[k] - q[k]) for p, q in zip(held["final"], solved["final"]) for k in ("x", "y", "theta"))
        evals = f"{held['newton_work']['evaluations']} evaluations instead of {solved['newton_work']['evaluations']}"
        solves = (f"the same {held['linear_solves']} linear solves" if held["linear_solves"] == solved["linear_solves"]
                  else f"{held['linear_solves']} linear solves instead of {solved['linear_solves']}")
        poses = "the same final poses" if apart == 0 else f"final poses within {sci(apart)}"
        parted = parting(*dirs) if out[0] else None
        if parted:
            t, before = parted
            poses = (f"poses within {sci(before)} until t = {float(t):.10g}, where the two runs' Newton iterations "
                     f"reach different solutions of one step ({sci(apart)} apart at the end)")
        return held, solved, evals, solves, poses
    pile, _, evals, _, poses = pair("pile", "blocks", "run", "examples/scenes/pile-at-rest.toml")
    _, _, l_evals, l_solves, l_poses = pair("lire", "blocks", "lire", "--perturb", "bottom", "--floor", "--t-end", "30")
    drums, _, d_evals, d_solves, d_poses = pair("drums", "blocks", "run", "drum-column")
    record, _, _, _, _ = pair("record", "blocks", "run", "examples/scenes/drums-on-record.toml")
    _, still, _, _, _ = pair("none", "blocks", "lire", "--perturb", "none")
    tilt = max(abs(b["theta"]) for b in still["final"])
    text = (
        f"the pile's run (`rollstack blocks run examples/scenes/pile-at-rest.toml --json`) takes "
        f"{evals}, {poses}; the Lire tower collapsing onto a floor (`rollstack blocks lire "
        f"--perturb bottom --floor --t-end 30 --json`) comes to rest leaning on itself and takes "
        f"{l_evals}, {l_solves}, {l_poses} (the run that solves every step keeps moving by the "
        f"round-off of its velocities). The drum column the pulse topples (`rollstack blocks run "
        f"drum-column --json`) lies at rest on the floor for {drums['resting_steps']} of its "
        f"{drums['steps']} steps: {d_evals}, {d_solves}, {d_poses}; the drums on a record "
        f"(`examples/scenes/drums-on-record.toml`) rest for {record['resting_steps']} of its "
        f"{record['steps']} steps, after the record. The tower in exact unstable equilibrium "
        f"(`blocks lire --perturb none`) is held there; solving every step, round-off tips it by "
        f"{sci(tilt)} rad by t = 10"
    )
    return "\n".join(textwrap.wrap(text, 88, break_long_words=False, break_on_hyphens=False))


def tallest_column(r):
    """method.md §8.2, tall columns: 10 steps of the 10 000-block column moving with its
    base at Δt = 0.005 (about 15 s)."""
    d = r.json("blocks", "shake", "--blocks", "10000", "--omega", "2", "--amplitude", "0.001",
               "--mu", "0.2", "--steps-per-period", "628", "--t-end", "0.05", "--start-with-base",
               "--json")
    if d.get("error") or d["steps"] != 10:
        sys.exit(f"the 10 000-block column: {d['steps']} steps, {d.get('error')}")
    return f"{d['linear_solves']} linear solves"


def worst_run_phases(r):
    """method.md §8.2, "Where the matrix's worst run goes": the run (6, 2, 0.5) of the
    reference matrix to the times its blocks land, and its step from t = 5.7177 (a second)."""
    shake = ["blocks", "shake", "--blocks", "6", "--omega", "2", "--mu", "0.5",
             "--steps-per-period", "200", "--json"]

    def counts(t_end):
        d = r.json(*shake, "--t-end", t_end)
        return d, (d["steps"], d["linear_solves"], d["newton_work"]["evaluations"])

    runs = [counts(t) for t in ("4.7", "8.5", "20")]
    landed = sorted((e["t"], e["block"]) for e in runs[-1][0]["events"] if e["kind"] == "touched_floor")
    if len(landed) != 4 or not landed[2][0] < 4.7 < landed[3][0] < 8.5:
        sys.exit(f"(6, 2, 0.5): the blocks land at {landed}, not as method.md §8.2 tells")
    (before, at), (_, after) = counts("5.71"), counts("5.72")
    if after[0] != at[0] + 1:
        sys.exit("(6, 2, 0.5): --t-end 5.71 and 5.72 do not bracket one step")
    what = (
        f"to t = 4.7, the column falling apart (the third block lands at t = {landed[2][0]:.2f})",
        f"to t = 8.5, block {landed[3][1]} leaning on the shaken base against a block on the floor "
        f"(it lands at t = {landed[3][0]:.2f})",
        "to t = 20, two blocks sliding on the base beside four held on the floor",
    )
    ends = [c for _, c in runs]
    phases = [[b - a for a, b in zip(prev, end)] for prev, end in zip([(0, 0, 0)] + ends, ends)]
    text = "; ".join(
        f"{w}: {steps} steps, {solves} linear solves, {evaluations} evaluations"
        for w, (steps, solves, evaluations) in zip(what, phases)
    )
    text += (
        f". Its step from t = {before['t_final']:.4f} takes {after[1] - at[1]} of its "
        f"{ends[-1][1]} linear solves"
    )
    return "\n".join(textwrap.wrap(text, 88, break_long_words=False, break_on_hyphens=False))


# doc file, marker name, function of the runner giving the text between the markers.
NUMBERS = [
    ("docs/method.md", "reference_counts", reference_counts),
    ("docs/tuning.md", "matrix_counts", matrix_counts),
    ("docs/exploration.md", "lire_convergence", lire_convergence),
    ("docs/method.md", "rest_counts", rest_counts),
    ("docs/method.md", "tallest_column", tallest_column),
    ("docs/method.md", "worst_run_phases", worst_run_phases),
]


def replaced(text, name, value):
    """`text` with the span between NAME's markers set to `value`."""
    begin, end = f"<!-- {name}: begin -->", f"<!-- {name}: end -->"
    pattern = re.compile(re.escape(begin) + ".*?" + re.escape(end), re.S)
    if len(pattern.findall(text)) != 1:
        sys.exit(f"expected one pair of {name} markers")
    return pattern.sub(lambda _: begin + value + end, text)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("binary", help="a release rollstack")
    parser.add_argument("--check", action="store_true", help="only compare; exit 1 on a difference")
    parser.add_argument("--only", default="", help="comma-separated marker names")
    args = parser.parse_args()
    only = set(filter(None, args.only.split(",")))
    unknown = only - {name for _, name, _ in NUMBERS}
    if unknown:
        sys.exit(f"--only: unknown entries {sorted(unknown)} (entries: {', '.join(n for _, n, _ in NUMBERS)})")
    differ = False
    with tempfile.TemporaryDirectory() as tmp:
        runner = Runner(os.path.abspath(args.binary), tmp)
        for doc, name, make in NUMBERS:
            if only and name not in only:
                continue
            path = os.path.join(ROOT, doc)
            old = open(path, encoding="utf-8").read()
            new = replaced(old, name, make(runner))
            if new == old:
                print(f"{doc} {name}: the same")
                continue
            differ = True
            if args.check:
                diff = difflib.unified_diff(old.splitlines(), new.splitlines(), doc, "program", lineterm="")
                print("\n".join(diff))
            else:
                open(path, "w", encoding="utf-8").write(new)
                print(f"{doc} {name}: rewritten")
    if args.check and differ:
        sys.exit(1)


if __name__ == "__main__":
    main()
