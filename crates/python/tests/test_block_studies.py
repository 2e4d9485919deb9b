"""`blocks.painleve`, `blocks.work_precision` and the branches of the sweeps: the
command line's `blocks painleve`, `blocks work-precision` and `--branches`."""

import math

import numpy as np
import pytest

from helpers import cells, exits_on_sigint, read_csv, strip_timings
from rollstack import blocks


def test_painleve_equals_cli(cli, tmp_path):
    ours = blocks.painleve(0.5, mu=0.3, mu_max=2.0, grid=6)
    theirs = cli("blocks", "painleve", "--aspect", "0.5", "--mu", "0.3", "--mu-max", "2",
                 "--grid", "6", "--out", str(tmp_path))
    assert ours["report"] == theirs
    grid = read_csv(tmp_path / "painleve_b_grid.csv")
    # The CSV runs over ϑ fastest, then μ: the arrays' rows are μ.
    assert cells(grid["theta_rad"][:6]) == ours["theta"].tolist()
    assert cells(grid["mu_d"][::6]) == ours["mu"].tolist()
    assert cells(grid["b_slip_positive"]) == ours["b_slip_positive"].ravel().tolist()
    assert cells(grid["b_slip_negative"]) == ours["b_slip_negative"].ravel().tolist()
    assert [a == "1" for a in grid["admissible"][:6]] == ours["admissible"].tolist()


def test_painleve_least_friction_is_its_closed_form():
    # (1 + 4 tan²ϑ) / (3 |tan ϑ|): least, 4/3, at tan ϑ = ±1/2 (App. I, ERRATA 18); a block
    # of w/h = 0.2 cannot lean to tan ϑ = 1/2 on the side of positive slip, so that
    # side's least value is at the end of its range, tan ϑ_max = 0.2.
    out = blocks.painleve(0.2)
    r = out["report"]
    assert r["mu_min"] == pytest.approx(4 / 3, abs=1e-12)
    assert r["theta_max"] == pytest.approx(math.atan(0.2), abs=1e-15)
    assert r["theta_min"] == pytest.approx(-math.atan(5.0), abs=1e-15)
    assert r["mu_min_slip_positive"]["mu"] == pytest.approx((1 + 4 * 0.04) / 0.6, abs=1e-12)
    assert r["mu_min_slip_negative"]["theta"] == pytest.approx(-math.atan(0.5), abs=1e-12)
    # b = 1 + 3 sin²ϑ − 3 μ sin ϑ cos ϑ sgn(ẋ_P) (I.1.8) on the grid.
    theta, mu = np.meshgrid(out["theta"], out["mu"])
    b = 1 + 3 * np.sin(theta) ** 2 - 3 * mu * np.sin(theta) * np.cos(theta)
    assert out["b_slip_positive"].shape == (121, 121)
    np.testing.assert_allclose(out["b_slip_positive"], b, atol=1e-12)
    assert out["mu"][-1] == 3.0


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(aspect=math.nan), "aspect"),
        (dict(aspect=-1.0), "aspect"),
        (dict(aspect="wide"), "aspect"),
        (dict(aspect=0.5, mu=-0.1), "mu"),
        (dict(aspect=0.5, mu=math.inf), "mu"),
        (dict(aspect=0.5, mu_max=0.0), "mu_max"),
        (dict(aspect=0.5, grid=1), "grid"),
        (dict(aspect=0.5, grid=-3), "grid"),
        (dict(aspect=0.5, grid=2.5), "grid"),
        (dict(aspect=0.5, grid=10**6), "grid"),
    ],
)
def test_painleve_bad_input(kwargs, name):
    with pytest.raises(ValueError, match=name):
        blocks.painleve(**kwargs)


def test_work_precision_equals_cli(cli):
    ours = blocks.work_precision("block", dts=[1e-2, 5e-3], reference_factor=2, repeat=1)
    theirs = cli("blocks", "work-precision", "--system", "block", "--dts", "0.01,0.005",
                 "--reference-factor", "2", "--repeat", "1")
    assert strip_timings(ours) == strip_timings(theirs)
    assert [r["scheme"] for r in ours["rows"]] == ["nsga", "nsga", "moreau", "moreau"]


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(system="tower"), "system"),
        (dict(dts=[math.nan]), "dts"),
        (dict(dts=[-1e-3]), "dts"),
        (dict(dts=[]), "dts"),
        (dict(dts="0.01"), "dts"),
        (dict(dts=[1e-2, None]), "dts"),
        (dict(reference_factor=0.5), "reference_factor"),
        (dict(reference_factor=math.nan), "reference_factor"),
        (dict(repeat=0), "repeat"),
        (dict(repeat=1001), "repeat"),
        (dict(repeat=-1), "repeat"),
    ],
)
def test_work_precision_bad_input(kwargs, name):
    with pytest.raises(ValueError, match=name):
        blocks.work_precision(**kwargs)


def test_an_endless_work_precision_is_refused_unless_forced():
    with pytest.raises(ValueError, match="more than 600 s") as e:
        blocks.work_precision(dts=[1e-300])
    assert "force=True" in str(e.value) and "reference_factor" in str(e.value)


def test_ctrl_c_interrupts_a_long_work_precision_study():
    exits_on_sigint("blocks.work_precision('block', dts=[1e-5], repeat=1, force=True)")


def test_sweep_frequency_branches_equal_cli(cli):
    rows = blocks.sweep_frequency([6.0, 9.0], periods=1.0, blocks=2, branches=3)
    theirs = cli("blocks", "sweep", "frequency", "--omega", "6,9", "--periods", "1",
                 "--blocks", "2", "--branches", "3")
    assert strip_timings(rows) == strip_timings(theirs["rows"])
    assert all(1 <= r["branches"] <= 3 for r in rows)
    # The command line's spelling of the rule gives the same rows.
    dashed = blocks.sweep_frequency([6.0, 9.0], periods=1.0, blocks=2, branches=3,
                                    branch_rule="self-consistent")
    assert strip_timings(dashed) == strip_timings(rows)


def test_sweep_slide_branches_equal_cli(cli):
    rows = blocks.sweep_slide([0.3], t_end=0.3, blocks=2, branches=2, branch_rule="converged")
    theirs = cli("blocks", "sweep", "slide", "--v0", "0.3", "--t-end", "0.3", "--blocks", "2",
                 "--branches", "2", "--branch-rule", "converged")
    assert strip_timings(rows) == strip_timings(theirs["rows"])


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(branches=0), "branches"),
        (dict(branches=-1), "branches"),
        (dict(branches=1.5), "branches"),
        (dict(branch_rule="any"), "branch_rule"),
    ],
)
def test_sweep_branches_bad_input(kwargs, name):
    with pytest.raises(ValueError, match=name):
        blocks.sweep_frequency([6.0], periods=1.0, blocks=2, **kwargs)
    with pytest.raises(ValueError, match=name):
        blocks.sweep_slide([0.3], t_end=0.3, blocks=2, **kwargs)


def test_explore_takes_either_spelling_of_the_rule():
    scene = blocks.lire(blocks=2)
    dashed = blocks.explore(scene, t_end=0.1, max_branches=1, branch_rule="self-consistent")
    plain = blocks.explore(scene, t_end=0.1, max_branches=1, branch_rule="self_consistent")
    assert dashed["branch_rule"] == plain["branch_rule"] == "self_consistent"
    assert strip_timings(dashed) == strip_timings(plain)


def test_converge_equals_cli(cli):
    # The Lire collapse to t = 6.7 at Δt and Δt/2 with one member per magnitude: the
    # failure at 6.600 and 6.595 is converged.
    ours = blocks.converge("lire-collapse", levels=1, ensemble=1, t_end=6.7)
    theirs = cli("blocks", "converge", "lire-collapse", "--levels", "1", "--ensemble", "1",
                 "--t-end", "6.7")
    for key in ("files", "notes"):
        theirs.pop(key)
    assert strip_timings(ours) == strip_timings(theirs)
    assert ours["failure"]["verdict"] == "converged"
    assert [r["label"] for r in ours["runs"]] == [
        "level0", "level1", "member01", "member02", "member03"]
    scene = blocks.Scene.builtin("lire-collapse")
    again = blocks.converge(scene, levels=1, ensemble=0, t_end=6.7)
    assert strip_timings(again["runs"][:2]) == strip_timings(ours["runs"][:2])


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(levels=0), "levels"),
        (dict(levels=9), "levels"),
        (dict(levels=-1), "levels"),
        (dict(levels=1.5), "levels"),
        (dict(ensemble=21), "ensemble"),
        (dict(t_end=-1.0), "t_end"),
        (dict(t_end="long"), "t_end"),
    ],
)
def test_converge_refuses_naming_the_parameter(kwargs, name):
    with pytest.raises(ValueError, match=name):
        blocks.converge("lire", **kwargs)


def test_sweep_convergence_equals_cli(cli):
    # `convergence=K` is `--convergence K`: the rows gain their verdicts over Δt/2^k;
    # without it they have no `convergence` key.
    rows = blocks.sweep_frequency([4.0], t_max=5.0, convergence=1)
    theirs = cli("blocks", "sweep", "frequency", "--omega", "4", "--t-max", "5",
                 "--convergence", "1")
    assert strip_timings(rows) == strip_timings(theirs["rows"])
    c = rows[0]["convergence"]
    assert (c["levels"], c["ensemble"], len(c["failure_times"])) == (1, 0, 2)
    assert c["failure_times"][0] == rows[0]["failure_time"]
    plain = blocks.sweep_frequency([4.0], t_max=5.0)
    assert "convergence" not in plain[0]
    slide = blocks.sweep_slide([0.5], t_end=0.3, blocks=2, convergence=1, ensemble=1)
    theirs = cli("blocks", "sweep", "slide", "--v0", "0.5", "--t-end", "0.3", "--blocks", "2",
                 "--convergence", "1", "--ensemble", "1")
    assert strip_timings(slide) == strip_timings(theirs["rows"])
    scene = blocks.sweep_scene(blocks.Scene.builtin("shaking"), {"contact.mu": [0.2]},
                               t_end=0.3, convergence=1)
    assert scene[0]["convergence"]["levels"] == 1


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(convergence=0), "convergence"),
        (dict(convergence=9), "convergence"),
        (dict(convergence=1.5), "convergence"),
        (dict(convergence=1, ensemble=21), "ensemble"),
        (dict(ensemble=1), "ensemble"),
    ],
)
def test_sweep_convergence_bad_input(kwargs, name):
    with pytest.raises(ValueError, match=name):
        blocks.sweep_frequency([6.0], periods=1.0, blocks=2, **kwargs)
    with pytest.raises(ValueError, match=name):
        blocks.sweep_slide([0.3], t_end=0.3, blocks=2, **kwargs)
