"""Comparison helpers for the tests."""

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
