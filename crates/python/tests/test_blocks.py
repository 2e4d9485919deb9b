import re

import numpy as np
import pytest

import rollstack
from helpers import exits_on_sigint, strip_timings
from rollstack import blocks

ONE_BLOCK = dict(
    base={"width": 1.0, "height": 0.2, "motion": "fixed"},
    blocks=[{"width": 1.0, "height": 0.2, "mass": 1.0, "x": 0.1}],
    contact={"mu": 0.3},
    solver={"dt": 0.01, "t_end": 0.1},
)


def cli_report(json_out):
    """The CLI's run JSON without what only the CLI has (files, notes) and timings."""
    out = {k: v for k, v in json_out.items() if k not in ("files", "notes")}
    return strip_timings(out)


def test_scene_from_kwargs_dict_toml_and_builtin(tmp_path):
    a = blocks.Scene(**ONE_BLOCK)
    b = blocks.Scene.from_dict(ONE_BLOCK)
    assert a.n_blocks == b.n_blocks == 1
    assert a.report() == b.report()
    path = tmp_path / "one.toml"
    path.write_text(a.toml)
    c = blocks.Scene.from_toml(str(path))
    assert c.title == "one" and c.report() == a.report()
    assert blocks.Scene.from_toml(a.toml).report() == a.report()
    names = blocks.scenes()
    assert {"lire", "shaking", "slide"} <= set(names)
    assert blocks.Scene.builtin("lire").n_blocks == 4
    assert "Scene(" in repr(a)


@pytest.mark.parametrize(
    "tables, message",
    [
        ({**ONE_BLOCK, "colour": "red"}, "colour"),
        ({**ONE_BLOCK, "contact": {"mu": -1.0}}, "mu"),
        ({**ONE_BLOCK, "blocks": [{"width": -1.0, "height": 0.2, "mass": 1.0, "x": 0.0}]}, "width"),
    ],
)
def test_bad_scene_is_a_value_error(tables, message):
    with pytest.raises(ValueError, match=message):
        blocks.Scene.from_dict(tables)


def test_bad_scene_sources():
    with pytest.raises(ValueError):
        blocks.Scene.from_toml("[base\nwidth = 1")
    with pytest.raises(ValueError, match="built-in"):
        blocks.Scene.builtin("no-such-scene")
    with pytest.raises(ValueError):
        blocks.Scene.from_dict({"x": object()})


def test_simulate_arrays_shapes_dtypes():
    r = blocks.simulate(blocks.Scene(**ONE_BLOCK))
    assert r.steps == 10
    n = r.steps + 1
    assert r.t.shape == (n,) and r.t.dtype == np.float64
    for name in ("q", "u", "forces"):
        assert getattr(r, name).shape == (n, 1, 3), name
        assert getattr(r, name).dtype == np.float64
    assert r.gaps.shape == (n, 1, 2)
    assert r.base.shape == (n, 3)
    assert r.min_gap.shape == r.energy.shape == (n,)
    assert r.iterations.dtype == np.int64
    # A block resting on a fixed table: the normal forces carry its weight.
    np.testing.assert_allclose(r.forces[-1, 0, :2].sum(), 1.0, rtol=1e-6)
    np.testing.assert_allclose(r.q[-1, 0], [r.report["final"][0][k] for k in ("x", "y", "theta")])
    assert r.report["t_final"] == r.t[-1]
    assert r.error is None and isinstance(r.events, list)


def test_a_trilith_has_forces_per_interface_and_its_events_name_the_post():
    # Two posts and a lintel: 3 blocks, 4 interfaces (base/1, base/2, 1/3, 2/3).
    text = re.sub(r"amplitude = [0-9.]+", "amplitude = 0.3", blocks.Scene.builtin("trilith").toml)
    r = blocks.simulate(blocks.Scene.from_toml(text), t_end=3.0)
    n = r.steps + 1
    assert r.q.shape == (n, 3, 3)
    assert r.forces.shape == (n, 4, 3) and r.gaps.shape == (n, 4, 2)
    # Both of the lintel's interfaces carry it at the start (at rest: half its weight
    # each, which the_lintel_weight_splits_equally_between_the_posts checks).
    assert (r.forces[0, 2:, :2].sum(axis=1) > 0).all()
    lost = [e for e in r.events if e["kind"] == "support_lost"]
    assert lost[0]["block"] == 3 and lost[0]["on"] in ("block 1", "block 2"), lost
    assert all("on" not in e for e in lost if e["block"] != 3), lost


def test_simulate_bad_options():
    scene = blocks.Scene(**ONE_BLOCK)
    with pytest.raises(ValueError, match="t_end"):
        blocks.simulate(scene, t_end=-1.0)
    with pytest.raises(ValueError, match="prox_constant"):
        blocks.simulate(scene, prox_constant=0.0)
    with pytest.raises(TypeError):
        blocks.simulate(ONE_BLOCK)


def test_lire_equals_cli(cli):
    r = blocks.simulate(blocks.lire(perturb="bottom"), t_end=2.0)
    theirs = cli("blocks", "lire", "--perturb", "bottom", "--t-end", "2")
    assert strip_timings(r.report) == cli_report(theirs)
    assert r.q.shape == (r.steps + 1, 4, 3)
    kinds = {e["kind"] for e in r.events}
    assert kinds <= {"branch_point", "failure", "opening", "error"}
    assert [e["t"] for e in r.events] == sorted(e["t"] for e in r.events)


def test_run_scene_file_equals_cli(cli, tmp_path):
    path = tmp_path / "one.toml"
    path.write_text(blocks.Scene(**ONE_BLOCK).toml)
    r = blocks.simulate(blocks.Scene.from_toml(str(path)))
    assert strip_timings(r.report) == cli_report(cli("blocks", "run", str(path)))


def test_shaking_equals_cli(cli):
    r = blocks.simulate(blocks.shaking(blocks=3, omega=6.0, amplitude=0.1, periods=1.0))
    theirs = cli("blocks", "shake", "--blocks", "3", "--omega", "6", "--amplitude", "0.1", "--periods", "1")
    assert strip_timings(r.report) == cli_report(theirs)
    r = blocks.simulate(blocks.shaking(blocks=3, omega=6.0, amplitude=0.1, periods=1.0, start_with_base=True))
    theirs = cli(
        "blocks", "shake", "--blocks", "3", "--omega", "6", "--amplitude", "0.1", "--periods", "1", "--start-with-base"
    )
    assert strip_timings(r.report) == cli_report(theirs)


def test_low_rank_updates_off_equals_cli(cli):
    scene = blocks.shaking(blocks=3, omega=6.0, amplitude=0.1, periods=1.0)
    off = blocks.simulate(scene, low_rank_updates=False)
    theirs = cli(
        "blocks", "shake", "--blocks", "3", "--omega", "6", "--amplitude", "0.1", "--periods", "1",
        "--low-rank-updates", "false",
    )
    assert strip_timings(off.report) == cli_report(theirs)
    on = blocks.simulate(scene)
    assert on.report["linear_solves"] <= off.report["linear_solves"]


def test_presets_bad_input():
    with pytest.raises(ValueError, match="perturb"):
        blocks.lire(perturb="middle")
    with pytest.raises(ValueError, match="blocks"):
        blocks.lire(blocks=0)
    with pytest.raises(ValueError, match="omega"):
        blocks.shaking(omega=0.0)
    with pytest.raises(ValueError, match="mu"):
        blocks.sliding(mu=-0.1)


def test_sliding_runs():
    r = blocks.simulate(blocks.sliding(blocks=2, v0=0.5, t_end=0.2))
    assert r.q.shape[1] == 2 and r.error is None


def test_sweep_frequency_equals_cli(cli):
    rows = blocks.sweep_frequency([3.0, 6.0, 9.0], periods=1.0, blocks=2)
    theirs = cli("blocks", "sweep", "frequency", "--omega", "3,6,9", "--periods", "1", "--blocks", "2")
    assert strip_timings(rows) == strip_timings(theirs["rows"])
    assert [r["omega"] for r in rows] == [3.0, 6.0, 9.0]


def test_sweep_frequency_with_a_horizon_equals_cli(cli):
    rows = blocks.sweep_frequency([3.0, 6.0], t_max=1.0, blocks=2)
    theirs = cli("blocks", "sweep", "frequency", "--omega", "3,6", "--t-max", "1", "--blocks", "2")
    assert strip_timings(rows) == strip_timings(theirs["rows"])
    assert [r["horizon"] for r in rows] == pytest.approx([1.0, 1.0], abs=1e-12)
    assert all(r["outcome"] in ("failed", "no_failure_by_horizon") for r in rows)


def test_sweep_slide_equals_cli(cli):
    rows = blocks.sweep_slide([0.1, 0.3], t_end=0.3, blocks=2)
    theirs = cli("blocks", "sweep", "slide", "--v0", "0.1,0.3", "--t-end", "0.3", "--blocks", "2")
    assert strip_timings(rows) == strip_timings(theirs["rows"])


def test_sweeps_bad_input():
    with pytest.raises(ValueError, match="omega"):
        blocks.sweep_frequency([2.0, -1.0])
    with pytest.raises(ValueError, match="t_end"):
        blocks.sweep_slide([0.1], t_end=0.0)


def test_sweep_scene_equals_cli(cli, tmp_path):
    path = tmp_path / "one.toml"
    path.write_text(blocks.Scene(**ONE_BLOCK).toml)
    scene = blocks.Scene.from_toml(str(path))
    rows = blocks.sweep_scene(scene, {"contact.mu": [0.1, 0.5], "blocks.x": "0.0,0.2"})
    theirs = cli("blocks", "sweep", "scene", str(path), "--set", "contact.mu=0.1,0.5",
                 "--set", "blocks.x=0.0,0.2")
    assert strip_timings(rows) == strip_timings(theirs["rows"])
    assert len(rows) == 4


def test_sweep_scene_bad_input():
    scene = blocks.Scene(**ONE_BLOCK)
    with pytest.raises(ValueError, match="colour"):
        blocks.sweep_scene(scene, {"contact.colour": [1.0]})
    with pytest.raises(ValueError):
        blocks.sweep_scene(scene, {"contact.mu": [-1.0]})
    with pytest.raises(ValueError, match="TOML"):
        blocks.sweep_scene(blocks.lire(), {"contact.mu": [0.1]})


def test_solver_error_carries_the_partial_result():
    # Newton cannot reach a tolerance of 1e-300, and without the last resort the first
    # step that fails ends the run.
    tables = {**ONE_BLOCK, "solver": {"dt": 0.01, "t_end": 0.1, "tol": 1e-300}}
    with pytest.raises(rollstack.SolverError) as info:
        blocks.simulate(blocks.Scene.from_dict(tables), last_resort=False, explore_branches=False)
    result = info.value.result
    assert isinstance(result, blocks.Result)
    assert result.error and result.error in str(info.value)
    assert len(result.t) == result.steps + 1
    assert result.events[-1]["kind"] == "error"


def test_to_dataframe():
    pd = pytest.importorskip("pandas")
    r = blocks.simulate(blocks.Scene(**ONE_BLOCK))
    df = r.to_dataframe()
    assert isinstance(df, pd.DataFrame) and len(df) == len(r.t)
    assert {"t", "x1", "n1a", "vx1", "g1a", "energy"} <= set(df.columns)


def test_ctrl_c_interrupts_a_long_simulation():
    # Forced: at 20 µs per block and step, the time guard would refuse it up front.
    exits_on_sigint(
        "blocks.simulate(blocks.shaking(blocks=4, omega=4.0, periods=100000.0), force=True)"
    )


def test_ctrl_c_interrupts_a_long_step():
    # A 3000-block column moving with its base starts in a fraction of a second and tips
    # in its third step, which takes more than a minute (docs/method.md §8.2, tall
    # columns): three seconds in, Ctrl-C must end the run within that step.
    exits_on_sigint(
        "blocks.simulate(blocks.shaking(blocks=3000, omega=2.0, amplitude=0.001, mu=0.2,"
        " steps_per_period=314.0, periods=1.0, start_with_base=True), force=True)",
        after=3.0,
    )


def test_ctrl_c_interrupts_a_long_sweep():
    # Two rows of 100000 periods each: the interrupt must end the runs already started,
    # not only keep new rows from starting.
    # Forced: the time guard would refuse them up front.
    exits_on_sigint(
        "blocks.sweep_frequency([0.5, 0.6], periods=100000.0, amplitude=0.001, force=True)"
    )


def test_help_has_the_docs():
    doc = blocks.simulate.__doc__
    assert "§4.2" in doc and "SolverError" in doc


def test_explore_reports_the_tree():
    scene = blocks.Scene.builtin("lire-collapse")
    tree = blocks.explore(scene, branch_rule="converged", max_branches=12, classify=True)
    # A fork is followed only when all its candidates fit under the cap.
    assert 2 <= tree["branches"] == len(tree["branch_rows"]) <= 12
    assert tree["branch_cap_reached"]
    assert tree["labels"]["real"] == 0
    assert len(tree["fork_rows"]) == tree["forks"]
    assert tree["branch_rows"][0]["id"] == "0" and tree["branch_rows"][0]["parent"] == ""


def test_explore_matches_the_command_line(cli):
    scene = blocks.Scene.builtin("lire-collapse")
    ours = blocks.explore(scene, branch_rule="converged", max_branches=8)
    theirs = cli("blocks", "explore", "lire-collapse", "--branch-rule", "converged", "--max-branches", "8")
    for key in ("branches", "leaves", "forks", "forks_followed", "labels", "outcomes", "steps"):
        assert ours[key] == theirs[key], key


def test_explore_bad_input():
    scene = blocks.Scene.builtin("lire")
    with pytest.raises(ValueError, match="strategy"):
        blocks.explore(scene, strategy="sideways")
    with pytest.raises(ValueError, match="branch_rule"):
        blocks.explore(scene, branch_rule="any")
    with pytest.raises(ValueError, match="max_branches"):
        blocks.explore(scene, max_branches=0)
    with pytest.raises(TypeError):
        blocks.explore("lire")


def test_a_collapse_on_a_floor_is_a_failure():
    # No block loses its support (failure_time None), but the top block reaches the floor.
    r = blocks.simulate(blocks.lire(perturb="bottom", floor=True), t_end=10)
    assert r.failure_time is None
    assert r.failure["kind"] == "touched_floor" and r.failure["block"] == 4
    assert 0 < r.failure["t"] < 10
    assert r.failure == r.report["failure"]


@pytest.mark.parametrize(
    "make",
    [
        lambda: blocks.shaking(blocks=10**9),
        lambda: blocks.lire(blocks=10**9),
        lambda: blocks.sliding(blocks=10**9),
        lambda: blocks.Scene(**{**ONE_BLOCK, "blocks": [{**ONE_BLOCK["blocks"][0], "count": 2**63 - 1}]}),
    ],
)
def test_block_counts_over_the_limit_are_refused_before_anything_is_built(make):
    # Before the check, the interpreter died: the blocks were allocated first.
    with pytest.raises(ValueError, match=r"must lie in \[1, 10000\]") as e:
        make()
    assert "blocks" in str(e.value) or "count" in str(e.value)


def test_an_endless_run_is_refused_up_front_unless_forced():
    scene = blocks.Scene(**ONE_BLOCK)
    with pytest.raises(ValueError, match="more than 600 s") as e:
        blocks.simulate(scene, t_end=1e300)
    assert "force=True" in str(e.value)
    # Forced, a short run goes as before.
    assert blocks.simulate(scene, t_end=0.05, force=True).steps == 5


@pytest.mark.parametrize(
    "sweep",
    [
        lambda force: blocks.sweep_frequency([4.0, 6.0], periods=1e9, force=force),
        lambda force: blocks.sweep_slide([0.1, 0.2], t_end=1e12, force=force),
        lambda force: blocks.sweep_scene(
            blocks.Scene(**ONE_BLOCK), {"solver.t_end": [0.1, 1e12]}, force=force
        ),
    ],
)
def test_an_endless_sweep_is_refused_up_front_unless_forced(sweep):
    # The CLI's sweeps refused these; the module ran them for days.
    with pytest.raises(ValueError, match="more than 600 s") as e:
        sweep(False)
    assert "force=True" in str(e.value) and "2 run(s)" in str(e.value)


def test_an_unreachable_wall_limit_is_no_limit():
    tree = blocks.explore(blocks.Scene(**ONE_BLOCK), max_branches=1, max_wall=1e20)
    assert not tree["wall_cap_reached"]
