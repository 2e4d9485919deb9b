"""The cost of one `simulate` call of a 10-step scene from Python, to set beside the
Rust benchmark (`cargo bench -p rollstack-python --bench overhead`, the same scene and
options). `pytest -s` prints the time; the test only guards against a gross regression.
"""

import time

from rollstack import blocks


def test_simulate_ten_steps_timing():
    scene = blocks.Scene.builtin("lire")
    for _ in range(20):
        blocks.simulate(scene, t_end=0.1)
    runs = 200
    best = float("inf")
    for _ in range(5):
        start = time.perf_counter()
        for _ in range(runs):
            r = blocks.simulate(scene, t_end=0.1)
        best = min(best, (time.perf_counter() - start) / runs)
    assert r.steps == 10
    solver = r.report["wall_time_s"]
    print(f"\nsimulate, 10 steps, from Python: {best * 1e6:.1f} µs per call (solver alone {solver * 1e6:.1f} µs)")
    assert best < 0.05
