import math

import numpy as np
import pytest

from helpers import strip_timings
from rollstack import sphere


def test_holonomy_equals_cli(cli):
    ours = sphere.holonomy(0.5, 0.2, 0.7)
    assert ours == cli("sphere", "holonomy", "--theta", "0.5", "--phi1", "0.2", "--phi2", "0.7")
    cw = sphere.holonomy(0.5, 0.2, 0.7, cw=True)
    assert cw == cli("sphere", "holonomy", "--theta", "0.5", "--phi1", "0.2", "--phi2", "0.7", "--cw")


def test_holonomy_bad_input():
    with pytest.raises(ValueError):
        sphere.holonomy(0.5, 0.9, 0.7)
    with pytest.raises(ValueError):
        sphere.holonomy(-1.0, 0.1, 0.7)


def test_plan_equals_cli(cli):
    angle = 3 * math.pi / 2
    axis = [0.1, 0.98994949, 0.1]
    ours = sphere.plan(angle, axis)
    theirs = cli("sphere", "plan", "--angle", repr(angle), "--axis", ",".join(repr(a) for a in axis))
    assert ours == theirs
    assert len(ours["rectangles"]) >= 1


def test_plan_bad_input():
    with pytest.raises(ValueError, match="axis"):
        sphere.plan(1.0, [0.0, 0.0, 0.0])
    with pytest.raises(ValueError):
        sphere.plan(1.0, [1.0, 0.0])


def test_euler_plan_equals_cli(cli):
    ours = sphere.euler_plan("3-1-3", [0.5, 0.4, -0.3])
    assert ours == cli("sphere", "euler-plan", "--set", "3-1-3", "--angles", "0.5,0.4,-0.3")


def test_euler_plan_bad_input():
    with pytest.raises(ValueError):
        sphere.euler_plan("3-3-1", [0.5, 0.4, -0.3])


def test_roll_equals_cli_and_arrays(cli):
    ours = sphere.roll(1.2, 0.3, 2.0, steps=200)
    theirs = cli("sphere", "roll", "--theta", "1.2", "--phi1", "0.3", "--phi2", "2.0", "--steps", "200")
    assert strip_timings(ours["report"]) == strip_timings(theirs)
    n = len(ours["s"])
    assert ours["s"].dtype == np.float64
    assert ours["centre"].shape == (n, 3) and ours["marked_point"].shape == (n, 3)
    assert ours["orientation"].shape == (n, 4)
    circle = sphere.roll(circle=2.0, integrator="rk4")
    assert circle["label"].startswith("circle")


def test_roll_bad_input():
    with pytest.raises(ValueError, match="one path"):
        sphere.roll(1.0, 0.2, 2.0, circle=1.0)
    with pytest.raises(ValueError, match="integrator"):
        sphere.roll(1.0, 0.2, 2.0, integrator="euler")
