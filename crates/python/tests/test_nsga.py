import numpy as np
import pytest

from helpers import exits_on_sigint, strip_timings
from rollstack import nsga


def test_ball_equals_cli(cli):
    ours = nsga.ball(2)
    theirs = cli("nsga", "ball", "--case", "2")
    assert strip_timings(ours["report"]) == strip_timings(theirs)
    n = len(ours["t"])
    assert ours["q"].shape == (n, 3) and ours["u"].shape == (n, 3)
    assert ours["p_n"].shape == (n,) and ours["iterations"].dtype == np.int64


def test_ball_bad_input():
    with pytest.raises(ValueError):
        nsga.ball(7)
    with pytest.raises(ValueError, match="dt"):
        nsga.ball(2, dt=0.0)
    with pytest.raises(ValueError, match="scheme"):
        nsga.ball(2, scheme="euler")


def test_work_precision_equals_cli(cli):
    ours = nsga.work_precision("oscillator", dts=[0.01, 0.005], rho_inf=[0.5], repeat=1)
    theirs = cli("nsga", "work-precision", "--system", "oscillator", "--dts", "0.01,0.005",
                 "--rho-inf", "0.5", "--repeat", "1")
    del theirs["csv"]
    assert strip_timings(ours) == strip_timings(theirs)
    assert [o["order"]["status"] for o in ours["orders"]] == ["fitted", "fitted"]


def test_work_precision_bad_input():
    with pytest.raises(ValueError):
        nsga.work_precision("pendulum")
    with pytest.raises(ValueError, match="dt"):
        nsga.work_precision("ball", dts=[1.0])


def test_ctrl_c_interrupts_a_long_work_precision_study():
    exits_on_sigint('nsga.work_precision("ball", dts=[1e-5], rho_inf=[0.5], repeat=1000)')
