import math

import numpy as np
import pytest

from helpers import exits_on_sigint, strip_timings

from rollstack import cylinders


def test_support_equals_cli(cli):
    ours = cylinders.support(0.5, r_over_h=0.1, mu=0.2)
    assert ours == cli("cylinder", "support", "--theta", "0.5", "--r-over-h", "0.1", "--mu", "0.2")
    weighed = cylinders.support(0.5, mass=2.0)
    assert weighed == cli("cylinder", "support", "--theta", "0.5", "--mass", "2.0")


def test_support_bad_input():
    with pytest.raises(ValueError):
        cylinders.support(0.5, r_over_h=-1.0)


def test_frobenius_equals_cli(cli):
    for system in ("single", "pair9"):
        ours = cylinders.frobenius(system=system)
        theirs = cli("cylinder", "frobenius", "--system", system)
        assert strip_timings(ours) == strip_timings(theirs)


def test_frobenius_bad_input():
    with pytest.raises(ValueError, match="system"):
        cylinders.frobenius(system="triple")
    with pytest.raises(ValueError):
        cylinders.frobenius(r=-1.0)


def test_frobenius_of_a_callable():
    # x' = 0: integrable. The knife edge: -sin(th) x' + cos(th) y' = 0 is not.
    flat = cylinders.frobenius_test(lambda q: [[1.0, 0.0, 0.0]], [0.1, 0.2, 0.3])
    assert flat["integrable"] == [True]
    knife = cylinders.frobenius_test(lambda q: [[-math.sin(q[2]), math.cos(q[2]), 0.0]], [0.1, 0.2, 0.3])
    assert knife["integrable"] == [False]
    assert knife["rank"] == 1 and knife["nullity"] == 2


def test_frobenius_callable_bad_input():
    with pytest.raises(ValueError, match="column"):
        cylinders.frobenius_test(lambda q: [[1.0, 0.0]], [0.1, 0.2, 0.3])

    def broken(q):
        raise ZeroDivisionError("mine")

    with pytest.raises(ZeroDivisionError, match="mine"):
        cylinders.frobenius_test(broken, [0.1, 0.2])


def test_holonomy_rectangle_equals_cli(cli):
    ours = cylinders.holonomy_rectangle(0.5, 1.0, 2.0, max_step=1e-2)
    theirs = cli("cylinder", "holonomy", "rectangle", "--theta", "0.5", "--phi1", "1.0",
                 "--phi2", "2.0", "--max-step", "0.01")
    assert strip_timings(ours["report"]) == strip_timings(theirs)
    n = len(ours["t"])
    assert ours["center"].shape == ours["contact"].shape == ours["rim_point"].shape == (n, 3)
    assert ours["phi"].shape == (n,)


def test_holonomy_circle_equals_cli(cli):
    ours = cylinders.holonomy_circle(2.0, 0.5, r_over_h=0.1, max_step=1e-2)
    theirs = cli("cylinder", "holonomy", "circle", "--ell", "2.0", "--theta", "0.5",
                 "--r-over-h", "0.1", "--max-step", "0.01")
    assert strip_timings(ours["report"]) == strip_timings(theirs)


def test_holonomy_bad_input():
    with pytest.raises(ValueError):
        cylinders.holonomy_rectangle(2.0, 1.0, 2.0)  # θ outside (0, π/2)
    with pytest.raises(ValueError, match="case"):
        cylinders.holonomy_rectangle(0.5, 1.0, 2.0, case="III")
    with pytest.raises(ValueError, match="height"):
        cylinders.holonomy_circle(2.0, 0.5)
    with pytest.raises(ValueError):
        cylinders.holonomy_circle(-2.0, 0.5, h=10.0)


def test_pair_equals_cli(cli, tmp_path):
    ours = cylinders.pair(0.5, steps=200)
    theirs = cli("cylinder", "pair", "--theta", "0.5", "--steps", "200", "--out", str(tmp_path))
    assert strip_timings(ours["report"]) == strip_timings(theirs)
    n = len(ours["t"])
    assert n == 201 and ours["t"].dtype == np.float64
    assert ours["q"].shape == (n, 12) and ours["gaps"].shape == (n, 3)
    assert ours["n_over_mg"].shape == (n, 2) and ours["contact_normal_force"].shape == (n,)
    # (3.3.10): N/mg of the smooth floor, and no force between the tanks.
    assert abs(ours["n_over_mg"][-1, 0] - ours["report"]["n_over_mg_static"]) < 1e-8
    assert abs(ours["contact_normal_force"][-1]) < 1e-8


def test_pair_bad_input():
    with pytest.raises(ValueError):
        cylinders.pair(0.01)  # below arctan(2r/h): the rim cannot touch
    with pytest.raises(ValueError):
        cylinders.pair(0.5, dt=-1e-3)
    with pytest.raises(ValueError):
        cylinders.pair(0.5, ramp=0.0)


def test_ctrl_c_interrupts_a_long_pair_run():
    # Forced: the time guard would refuse 10⁸ steps up front.
    exits_on_sigint("from rollstack import cylinders; cylinders.pair(0.5, steps=10**8, force=True)")


def test_no_silent_nan():
    # Each of these returned NaN arrays, or a rank-0 "not integrable" verdict, before.
    with pytest.raises(ValueError, match="psi0 is not finite"):
        cylinders.holonomy_rectangle(0.3, 1, 2, psi0=math.inf)
    with pytest.raises(ValueError, match=r"W\(q\) at row 0, column 0 is not finite"):
        cylinders.frobenius_test(lambda q: [[math.nan, 0.0]], [0.1, 0.2])
    with pytest.raises(ValueError, match="derivative of W"):
        cylinders.frobenius_test(lambda q: [[math.sqrt(q[0]) if q[0] >= 0 else math.nan, 0.0]], [0.0, 0.2])
    for bad in (math.nan, math.inf):
        with pytest.raises(ValueError, match="contact_at is not finite"):
            cylinders.frobenius(system="pair9", contact_at=bad)
        with pytest.raises(ValueError, match="contact_at"):
            cylinders.frobenius(contact_at=bad)
    with pytest.raises(ValueError, match="system='single'"):
        cylinders.frobenius(contact_at=0.3)
    assert cylinders.frobenius(system="pair7", contact_at=0.3)["rank"] == 7


def test_work_precision_equals_cli(cli):
    ours = cylinders.work_precision(math.pi / 6, dts=[2e-2, 1e-2], repeat=1)
    theirs = cli("cylinder", "work-precision", "--theta", "30deg", "--dts", "0.02,0.01",
                 "--repeat", "1")
    assert strip_timings(ours) == strip_timings(theirs)
    assert [r["scheme"] for r in ours["rows"]] == ["nsga", "nsga", "moreau", "moreau"]
    assert ours["orders"]["nsga"]["status"] in ("fitted", "not_in_asymptotic_range")


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(dts=[]), "dts"),
        (dict(dts=[-1e-3]), "dts"),
        (dict(dts=[2.0]), "dts"),
        (dict(dts=["x"]), "dts"),
        (dict(reference_factor=0.5), "reference_factor"),
        (dict(repeat=0), "repeat"),
        (dict(theta=0.05), "theta"),
    ],
)
def test_work_precision_bad_input(kwargs, name):
    with pytest.raises(ValueError, match=name):
        cylinders.work_precision(**kwargs)
