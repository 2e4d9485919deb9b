"""blocks.fragility: a slender block under three tiny one-sine records (docs/fragility.md)."""

import math

import numpy as np
import pytest

from rollstack import blocks

SCENE = """
[base]
width = 2.0
height = 0.2

[[blocks]]
width = 0.2
height = 1.0

[contact]
mu = 1.0
e_n = 0.0

[solver]
dt = 0.01
gravity = 9.81

[floor]
"""


def one_sine(peak, period):
    """A one-sine pulse of `peak` g and `period` s at 100 Hz, as t,a CSV."""
    lines = ["t,a"]
    for i in range(101):
        t = i * 0.01
        a = peak * math.sin(2 * math.pi * t / period) if t < period else 0.0
        lines.append(f"{t!r},{a!r}")
    return "\n".join(lines) + "\n"


@pytest.fixture
def records(tmp_path):
    d = tmp_path / "pulses"
    d.mkdir()
    for name, peak, period in [("a.csv", 1.5, 1.0), ("b.csv", 1.2, 0.8), ("c.csv", 0.9, 0.6)]:
        (d / name).write_text(one_sine(peak, period))
    return d


def test_a_study_returns_numpy_columns_and_the_four_fits(records):
    study = blocks.fragility(blocks.Scene.from_toml(SCENE), records, "0.1:1.5:0.1", t_end=2.5)
    assert study["record"][:2] == ["a.csv", "a.csv"] and study["record"][-1] == "c.csv"
    assert len(study["record"]) == 45
    for key in ("level", "pga_g", "pgv", "overturned", "failed", "failure_time", "wall_time_s"):
        assert isinstance(study[key], np.ndarray) and study[key].shape == (45,), key
    assert set(np.unique(study["overturned"])) <= {0.0, 1.0}
    assert np.isnan(study["failure_time"][0]) and study["failure_kind"][0] is None
    fits = study["fits"]
    assert [(f["outcome"], f["intensity"]) for f in fits] == [
        ("overturned", "pga"), ("overturned", "pgv"), ("failed", "pga"), ("failed", "pgv")]
    # The numbers of docs/fragility.md's example, as the command line prints them.
    assert f"{fits[0]['theta']:.4f}" == "0.4608" and f"{fits[0]['beta']:.3f}" == "0.765"
    lo, hi = fits[0]["theta_band"]
    assert lo < fits[0]["theta"] < hi
    assert fits[3]["theta"] is None and "separated" in fits[3]["no_fit"]


def test_target_pga_levels_and_a_list_of_files(records):
    files = [records / "b.csv", records / "a.csv"]
    study = blocks.fragility(blocks.Scene.from_toml(SCENE), files, [0.05, 0.1], measure="pga",
                             t_end=0.1)
    assert study["record"] == ["b.csv", "b.csv", "a.csv", "a.csv"]
    assert np.allclose(study["pga_g"], [0.05, 0.1, 0.05, 0.1], rtol=0, atol=1e-12)
    assert all(f["no_fit"].startswith("none of the 4 runs collapsed") for f in study["fits"])


def test_a_relative_records_directory_starts_from_the_working_directory(records, tmp_path,
                                                                        monkeypatch):
    # The scene's own record paths start from its file's directory; the records' do not.
    (tmp_path / "scenes").mkdir()
    (tmp_path / "scenes" / "block.toml").write_text(SCENE)
    monkeypatch.chdir(tmp_path)
    scene = blocks.Scene.from_toml("scenes/block.toml")
    study = blocks.fragility(scene, "pulses", [0.1], t_end=0.05)
    assert study["error"] == [None, None, None]


def test_bad_input_raises_value_error_naming_it(records, tmp_path):
    scene = blocks.Scene.from_toml(SCENE)
    empty = tmp_path / "empty"
    empty.mkdir()
    with pytest.raises(ValueError, match="records: .*holds no record"):
        blocks.fragility(scene, empty, 1.0)
    with pytest.raises(ValueError, match="scales: level 0: a target PGA"):
        blocks.fragility(scene, records, [0.0], measure="pga")
    with pytest.raises(TypeError, match="records must be a directory or a sequence"):
        blocks.fragility(scene, None, 1.0)
    with pytest.raises(ValueError, match="scales: cannot read value 'x'"):
        blocks.fragility(scene, records, "x")
    with pytest.raises(ValueError, match="measure must be 'scale' or 'pga'"):
        blocks.fragility(scene, records, 1.0, measure="pgv")
    (records / "d.csv").write_text("t,a\n0,0\n0.01,oops\n")
    with pytest.raises(ValueError, match="d.csv line 3"):
        blocks.fragility(scene, records, 1.0)
    with pytest.raises(ValueError, match=r"give \[solver\] dt"):
        blocks.fragility(blocks.Scene.builtin("shaking"), [records / "a.csv"], 1.0)
