"""Base excitations: recorded accelerograms and pulses as arrays, and scenes that play them."""

import os

import numpy as np
import pytest

from rollstack import blocks

RECORD = os.path.join(os.path.dirname(__file__), "..", "..", "..", "tests", "data", "synthetic.AT2")
EXAMPLE = os.path.join(
    os.path.dirname(__file__), "..", "..", "..", "examples", "scenes", "drums-on-record.toml"
)


def test_read_record_scales_corrects_and_integrates():
    r = blocks.read_record(RECORD, scale_to_pga=0.3, unit=9.81)
    assert set(r) == {"t", "a", "v", "d"}
    assert len(r["t"]) == 1000 and r["t"][1] == pytest.approx(0.01)
    assert np.max(np.abs(r["a"])) == pytest.approx(0.3 * 9.81, rel=1e-12)
    # The baseline correction ends the record at rest where it started.
    assert abs(r["v"][-1]) < 1e-12 and abs(r["d"][-1]) < 1e-12
    # v is the exact integral of the piecewise-linear a: the trapezoid rule.
    v = np.concatenate([[0.0], np.cumsum(0.5 * np.diff(r["t"]) * (r["a"][1:] + r["a"][:-1]))])
    assert np.allclose(r["v"], v, atol=1e-12)
    raw = blocks.read_record(RECORD, baseline="none")
    assert abs(raw["v"][-1]) > 0.0
    assert np.max(np.abs(raw["a"])) == pytest.approx(0.25, rel=1e-6)


def test_read_record_errors_name_the_file_and_line(tmp_path):
    bad = tmp_path / "bad.AT2"
    bad.write_text("PEER\nx\nACCELERATION IN G\nNPTS= 3, DT= .01\n.1 .2 oops\n")
    with pytest.raises(ValueError, match=r"record .*bad.AT2 line 5: 'oops' is not a number"):
        blocks.read_record(bad)
    csv = tmp_path / "one.csv"
    csv.write_text("0.1\n0.2\n0.3\n")
    with pytest.raises(ValueError, match="give its time step 'dt'"):
        blocks.read_record(csv)
    assert blocks.read_record(csv, dt=0.5, baseline="none")["t"][-1] == 1.0
    with pytest.raises(ValueError, match="unknown baseline"):
        blocks.read_record(csv, dt=0.5, baseline="linear")


def test_pulse_is_at_rest_before_it_starts_and_integrates_exactly():
    t = np.linspace(0.0, 3.0, 301)
    p = blocks.pulse("one-sine", 0.5, 2.0, t, start=0.5)
    assert np.all(p["v"][t <= 0.5] == 0.0) and np.all(p["d"][t <= 0.5] == 0.0)
    tau = np.clip(t - 0.5, 0.0, 2.0)
    w = np.pi
    assert np.allclose(p["v"], 0.5 / w * (1 - np.cos(w * tau)), atol=1e-15)
    assert p["d"][-1] == pytest.approx(0.5 * 4.0 / (2 * np.pi))
    with pytest.raises(ValueError, match="unknown pulse shape"):
        blocks.pulse("square", 1.0, 1.0, t)


def test_scenes_play_records_and_pulses():
    scene = blocks.Scene.from_toml(EXAMPLE)
    r = blocks.simulate(scene, t_end=0.1)
    assert r.error is None and len(r.t) == 51
    # The drums ride the table: they move as the base does (to the integrator's drift,
    # the friction holding the velocities together, not the positions).
    assert r.base[-1, 0] > 1e-4
    assert r.q[-1, 0, 0] == pytest.approx(r.base[-1, 0], rel=1e-3)
    heave = dict(
        base={
            "width": 1.0,
            "height": 0.1,
            "y": {"motion": "pulse", "shape": "ricker", "amplitude": 0.3, "period": 0.2},
        },
        blocks=[{"width": 0.2, "height": 0.4}],
        contact={"mu": 0.5},
        solver={"dt": 0.01, "t_end": 0.8},
    )
    r = blocks.simulate(blocks.Scene(**heave))
    assert r.report["scene"]["other_motions"] == {"y": "pulse"}
    expected = blocks.pulse("ricker", 0.3, 0.2, r.t)["d"] + 0.05 + 0.2
    assert np.allclose(r.q[:, 0, 1], expected, atol=1e-9)


def test_a_sweep_scales_a_record_beside_its_scene():
    scene = blocks.Scene.from_toml(EXAMPLE)
    rows = blocks.sweep_scene(scene, {"base.scale": [0.5, 1.0]}, t_end=0.1)
    assert [row["error"] for row in rows] == [None, None]
    assert rows[1]["top_x"] == pytest.approx(2 * rows[0]["top_x"], rel=1e-6)
