#!/usr/bin/env python3
"""Writes tests/data/synthetic.AT2: a made-up accelerogram in the PEER NGA .AT2 text
format, for the tests and the example scene of recorded base motions (no copyrighted
record is shipped). 10 s at 100 Hz: a sum of five sines under a rise-and-decay envelope,
peak 0.25 g, values in g written five per line in the Fortran form of the database
(`-.1234567E-02`). Deterministic: running it again writes the same bytes.

    python3 scripts/synthetic_record.py [OUT]
"""
import math
import sys

NPTS, DT, PGA = 1000, 0.01, 0.25
# (frequency Hz, relative amplitude, phase rad)
WAVES = [(0.7, 0.6, 0.3), (1.3, 1.0, 1.1), (2.1, 0.8, 2.0), (3.4, 0.5, 0.4), (5.5, 0.3, 2.7)]


def envelope(t):
    """Rises over the first second and a half, decays after (a Saragoni-Hart-like form)."""
    return (t / 1.5) ** 2 * math.exp(2.0 * (1.0 - t / 1.5)) if t > 0 else 0.0


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


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "tests/data/synthetic.AT2"
    raw = [envelope(i * DT) * sum(a * math.sin(2 * math.pi * f * i * DT + p) for f, a, p in WAVES)
           for i in range(NPTS)]
    peak = max(abs(v) for v in raw)
    acc = [PGA * v / peak for v in raw]
    lines = [
        "PEER NGA STRONG MOTION DATABASE RECORD",
        "SYNTHETIC TEST RECORD (scripts/synthetic_record.py), NOT AN EARTHQUAKE",
        "ACCELERATION TIME SERIES IN UNITS OF G",
        f"NPTS= {NPTS:5d}, DT= {DT:8.4f} SEC",
    ]
    for k in range(0, NPTS, 5):
        lines.append("".join(fortran(v) for v in acc[k:k + 5]))
    with open(out, "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
