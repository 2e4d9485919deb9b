#!/usr/bin/env python3
"""Writes made-up accelerograms in the PEER NGA .AT2 text format (no copyrighted record
is shipped), values in g written five per line in the Fortran form of the database
(`-.1234567E-02`). Deterministic: running it again writes the same bytes.

    python3 scripts/synthetic_record.py [OUT]

writes tests/data/synthetic.AT2 (or OUT), for the tests and the example scene of
recorded base motions: 10 s at 100 Hz, a sum of five sines under a rise-and-decay
envelope, peak 0.25 g.

    python3 scripts/synthetic_record.py --count 20 --duration 30 --dt 0.005 DIR

writes DIR/synthetic-01.AT2 ... synthetic-20.AT2 for a fragility study
(`rollstack blocks fragility SCENE --records DIR`): record k (from 1) is drawn with the
seed `--seed` + k, so that each differs from the others: five sines of frequencies
between 0.4 and 6 Hz with their own amplitudes and phases, an envelope rising over 1 to
4 s, a length between 3/4 of `--duration` and `--duration`, a peak between 0.1 and 0.5 g.
"""
import argparse
import math
import os
import random

NPTS, DT, PGA = 1000, 0.01, 0.25
# (frequency Hz, relative amplitude, phase rad)
WAVES = [(0.7, 0.6, 0.3), (1.3, 1.0, 1.1), (2.1, 0.8, 2.0), (3.4, 0.5, 0.4), (5.5, 0.3, 2.7)]


def envelope(t, rise=1.5):
    """Rises over the first `rise` seconds, decays after (a Saragoni-Hart-like form)."""
    return (t / rise) ** 2 * math.exp(2.0 * (1.0 - t / rise)) if t > 0 else 0.0


def fortran(v):
    """v as Fortran's E15.7 with the leading zero left out: ` -.1234567E-02`."""
    if v == 0.0:
        return "   .0000000E+00"
    e = math.floor(math.log10(abs(v))) + 1
    m = v / 10.0 ** e
    if round(abs(m), 7) >= 1.0:
        m, e = m / 10.0, e + 1
    digits = f"{abs(m):.7f}"[1:]  # ".1234567"
    return f"{'-' if m < 0 else ' '}{digits}E{e:+03d}".rjust(15)


def write_at2(out, acc, dt, title):
    """The accelerations `acc` (g) at step `dt` as an .AT2 file."""
    lines = [
        "PEER NGA STRONG MOTION DATABASE RECORD",
        title,
        "ACCELERATION TIME SERIES IN UNITS OF G",
        f"NPTS= {len(acc):5d}, DT= {dt:8.4f} SEC",
    ]
    for k in range(0, len(acc), 5):
        lines.append("".join(fortran(v) for v in acc[k:k + 5]))
    with open(out, "w") as f:
        f.write("\n".join(lines) + "\n")


def record(npts, dt, pga, waves, rise):
    """`npts` samples of the enveloped sum of `waves`, scaled to the peak `pga`."""
    raw = [envelope(i * dt, rise) * sum(a * math.sin(2 * math.pi * f * i * dt + p)
                                        for f, a, p in waves)
           for i in range(npts)]
    peak = max(abs(v) for v in raw)
    return [pga * v / peak for v in raw]


def many(directory, count, duration, dt, seed):
    """`count` distinct records in `directory` (module docs)."""
    os.makedirs(directory, exist_ok=True)
    width = max(2, len(str(count)))
    for k in range(1, count + 1):
        rng = random.Random(seed + k)
        waves = [(rng.uniform(0.4, 6.0), rng.uniform(0.2, 1.0), rng.uniform(0.0, 2 * math.pi))
                 for _ in range(5)]
        length = rng.uniform(0.75, 1.0) * duration
        npts = max(2, int(round(length / dt)))
        acc = record(npts, dt, rng.uniform(0.1, 0.5), waves, rng.uniform(1.0, 4.0))
        title = f"SYNTHETIC RECORD {k} OF {count}, SEED {seed + k} (scripts/synthetic_record.py), NOT AN EARTHQUAKE"
        write_at2(os.path.join(directory, f"synthetic-{k:0{width}d}.AT2"), acc, dt, title)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out", nargs="?", help="the file (default tests/data/synthetic.AT2), or the directory with --count")
    parser.add_argument("--count", type=int, help="write this many distinct records into the directory OUT")
    parser.add_argument("--duration", type=float, default=30.0, help="longest record, s (with --count; default 30)")
    parser.add_argument("--dt", type=float, default=0.005, help="time step, s (with --count; default 0.005, 200 Hz)")
    parser.add_argument("--seed", type=int, default=0, help="record k is drawn with seed SEED + k (with --count)")
    args = parser.parse_args()
    if args.count is not None:
        if args.out is None or args.count < 1 or args.duration <= 0 or args.dt <= 0:
            parser.error("--count N needs N >= 1, a directory OUT, and a positive --duration and --dt")
        many(args.out, args.count, args.duration, args.dt, args.seed)
        return
    out = args.out or "tests/data/synthetic.AT2"
    acc = record(NPTS, DT, PGA, WAVES, 1.5)
    write_at2(out, acc, DT, "SYNTHETIC TEST RECORD (scripts/synthetic_record.py), NOT AN EARTHQUAKE")


if __name__ == "__main__":
    main()
