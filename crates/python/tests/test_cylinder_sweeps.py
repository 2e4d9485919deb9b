"""`cylinders.statics`, `sweep_pair` and `sweep_push`: the command line's `cylinder
statics`, `cylinder sweep pair` and `cylinder sweep push`."""

import math
import subprocess

import pytest

from helpers import cells, exits_on_sigint, read_csv, strip_timings
from rollstack import cylinders


def test_statics_equals_the_cli_files(cli_exe, tmp_path):
    ours = cylinders.statics(r_over_h=0.12, mu=0.3, points=7)
    subprocess.run([cli_exe, "cylinder", "statics", "--r-over-h", "0.12", "--mu", "0.3",
                    "--points", "7", "--out", str(tmp_path)], check=True, capture_output=True)
    fig = read_csv(tmp_path / "fig3_3.csv")
    rows = ours["figure_3_3"]["rows"]
    assert cells(fig["theta"]) == [r["theta"] for r in rows]
    for key in ("n_over_mg_plus", "n_over_mg_smooth", "n_over_mg_minus"):
        assert cells(fig[key]) == [r[key] for r in rows], key
    minimum = read_csv(tmp_path / "fig3_7_fig3_8.csv")
    assert cells(minimum["circle_f3_over_mg"]) == [r["unconstrained"][0] for r in ours["minimum_force"]]
    assert cells(minimum["min_norm_over_mg"]) == [
        r["minimum"] and r["minimum"]["norm_over_mg"] for r in ours["minimum_force"]
    ]
    family = read_csv(tmp_path / "fig3_5.csv")
    assert len(family["mu"]) == sum(len(c["rows"]) for c in ours["figure_3_5"]) == 7 * 6


def test_statics_agrees_with_support():
    fig = cylinders.statics(points=9)
    assert len(fig["figure_3_3"]["rows"]) == 8
    for row in fig["figure_3_3"]["rows"]:
        one = cylinders.support(row["theta"], r_over_h=0.1, mu=0.2)
        for key in ("n_over_mg_plus", "n_over_mg_smooth", "n_over_mg_minus"):
            assert row[key] == one[key], (row["theta"], key)
    assert fig["self_balancing_theta"] == pytest.approx(math.atan(0.2), abs=1e-15)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(r_over_h=-0.1), "r_over_h"),
        (dict(r_over_h=math.nan), "r_over_h"),
        (dict(r_over_h="tall"), "r_over_h"),
        (dict(mu=-1.0), "mu"),
        (dict(mu=math.inf), "mu"),
        (dict(points=2), "points"),
        (dict(points=10**6), "points"),
        (dict(points=-1), "points"),
        (dict(points=3.5), "points"),
    ],
)
def test_statics_bad_input(kwargs, name):
    with pytest.raises(ValueError, match=name):
        cylinders.statics(**kwargs)


def test_sweep_pair_equals_cli(cli):
    rows = cylinders.sweep_pair("0.5,0.6", steps=60)
    theirs = cli("cylinder", "sweep", "pair", "--theta", "0.5,0.6", "--steps", "60")
    assert strip_timings(rows) == strip_timings(theirs["rows"])
    # A list of numbers is the same sweep; a row is the plain pair's run.
    assert strip_timings(cylinders.sweep_pair([0.5, 0.6], steps=60)) == strip_timings(rows)
    one = cylinders.pair(0.6, steps=60)["report"]
    assert rows[1]["n_over_mg"] == one["n_over_mg"] and rows[1]["drift"] == one["drift"]


def test_sweep_pair_reads_the_cli_s_angles(cli):
    rows = cylinders.sweep_pair("30deg:40deg:10deg", steps=20)
    assert [r["theta"] for r in rows] == pytest.approx([math.pi / 6, 2 * math.pi / 9], abs=1e-15)


def test_sweep_push_equals_cli(cli):
    rows = cylinders.sweep_push(0.6, push="0:0.3:0.1", steps=60)
    theirs = cli("cylinder", "sweep", "push", "--theta", "0.6", "--push", "0:0.3:0.1",
                 "--steps", "60")
    assert strip_timings(rows) == strip_timings(theirs["rows"])
    assert rows[0]["mu_floor"] == 0.2 and rows[0]["runs"] >= 1


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(theta=0.01), "theta"),
        (dict(theta=math.nan), "theta"),
        (dict(theta=[0.5, math.inf]), "theta"),
        (dict(theta="abc"), "theta"),
        (dict(theta=None), "theta"),
        (dict(theta=[]), "theta"),
        (dict(theta=0.5, dt=-1e-3), "dt"),
        (dict(theta=0.5, dt=math.nan), "dt"),
        (dict(theta=0.5, steps=0), "steps"),
        (dict(theta=0.5, steps=-5), "steps"),
        (dict(theta=0.5, steps="many"), "steps"),
    ],
)
@pytest.mark.parametrize("sweep", [cylinders.sweep_pair, cylinders.sweep_push])
def test_sweeps_bad_input(sweep, kwargs, name):
    with pytest.raises(ValueError, match=name):
        sweep(**kwargs)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(spin=math.nan), "spin"),
        (dict(spin="fast"), "spin"),
    ],
)
def test_sweep_pair_bad_spin(kwargs, name):
    with pytest.raises(ValueError, match=name):
        cylinders.sweep_pair(0.5, **kwargs)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(push="0.3:0:-0.1"), "push"),
        (dict(push=[0.1, math.nan]), "push"),
        (dict(push="x"), "push"),
        (dict(mu_floor=-0.2), "mu_floor"),
        (dict(mu_floor=math.nan), "mu_floor"),
    ],
)
def test_sweep_push_bad_input(kwargs, name):
    with pytest.raises(ValueError, match=name):
        cylinders.sweep_push(0.6, **kwargs)


@pytest.mark.parametrize(
    "run",
    [
        lambda force: cylinders.pair(0.5, steps=10**9, force=force),
        lambda force: cylinders.sweep_pair([0.5, 0.6], steps=10**9, force=force),
        lambda force: cylinders.sweep_push(0.6, push="0:0.5:0.01", steps=10**8, force=force),
    ],
)
def test_endless_pair_runs_are_refused_unless_forced(run):
    with pytest.raises(ValueError, match="more than 600 s") as e:
        run(False)
    assert "force=True" in str(e.value) and "steps" in str(e.value)


def test_ctrl_c_interrupts_a_long_pair_sweep():
    exits_on_sigint(
        "from rollstack import cylinders; cylinders.sweep_pair([0.5, 0.6], steps=10**8, force=True)"
    )


def test_ctrl_c_interrupts_a_long_push_sweep():
    exits_on_sigint(
        "from rollstack import cylinders; cylinders.sweep_push(0.6, push=[0.0, 0.1], steps=10**8, force=True)"
    )
