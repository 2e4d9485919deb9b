"""Comparison helpers for the tests."""

import signal
import subprocess
import sys
import textwrap
import time

TIMING_KEYS = {"wall_time_s", "solver_s", "total_s", "cpu_time_s", "time_s", "seconds"}


def strip_timings(value):
    """`value` without the keys that hold measured times (they differ between runs)."""
    if isinstance(value, dict):
        return {
            k: strip_timings(v)
            for k, v in value.items()
            if k not in TIMING_KEYS and not k.endswith("_s") and not k.startswith("wall")
        }
    if isinstance(value, list):
        return [strip_timings(v) for v in value]
    return value


def exits_on_sigint(body: str, after: float = 1.0) -> None:
    """Runs `body` (which has `blocks` and `nsga` imported and must take far longer than the test)
    in a child process, sends it SIGINT `after` seconds after it started and checks that it
    raised KeyboardInterrupt within a second.

    The child installs Python's SIGINT handler itself: a process started in the
    background by a non-interactive shell (`nohup`, a batch job) inherits SIGINT ignored,
    and Python then installs none, so the signal would never reach it."""
    child = textwrap.dedent(
        """
        import signal
        import sys
        signal.signal(signal.SIGINT, signal.default_int_handler)
        from rollstack import blocks, nsga
        print("started", flush=True)
        try:
            {body}
        except KeyboardInterrupt:
            print("interrupted", flush=True)
            sys.exit(3)
        print("finished", flush=True)
        """
    ).format(body=body)
    p = subprocess.Popen([sys.executable, "-c", child], stdout=subprocess.PIPE, text=True)
    assert p.stdout.readline().strip() == "started"
    time.sleep(after)
    sent = time.monotonic()
    p.send_signal(signal.SIGINT)
    try:
        code = p.wait(timeout=5)
    finally:
        if p.poll() is None:
            p.kill()
    elapsed = time.monotonic() - sent
    assert code == 3, p.stdout.read()
    assert elapsed < 1.0, elapsed


def read_csv(path):
    """The columns of a CSV file the command line wrote, by header, as text cells."""
    import csv

    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    return {key: [row[key] for row in rows] for key in rows[0]} if rows else {}


def cells(values):
    """Numbers as the cells of the command line's CSV: None (no value) as an empty cell,
    the others as floats to compare exactly (the CSV holds shortest round-trip forms)."""
    return [None if v in ("", None) else float(v) for v in values]
