import math

import numpy as np
import pytest

from rollstack import rotations


def test_convert_batched_shapes_and_dtypes():
    aa = np.array([[0.0, 0.0, 1.0, math.pi / 2], [1.0, 0.0, 0.0, 0.3], [0.0, 2.0, 0.0, 1.0]])
    q = rotations.axis_angle_to_quaternion(aa)
    assert q.dtype == np.float64 and q.shape == (3, 4)
    np.testing.assert_allclose(q[0], [math.cos(math.pi / 4), 0, 0, math.sin(math.pi / 4)], atol=1e-15)
    m = rotations.to_matrix(aa.reshape(3, 1, 4), "axis-angle")
    assert m.shape == (3, 1, 3, 3) and m.dtype == np.float64
    back = rotations.from_matrix(m, "axis-angle").reshape(3, 4)
    np.testing.assert_allclose(back[:, 3], aa[:, 3], atol=1e-12)
    np.testing.assert_allclose(back[2, :3], [0, 1, 0], atol=1e-12)
    aa_back = rotations.quaternion_to_axis_angle(q)
    np.testing.assert_allclose(aa_back[:, 3], aa[:, 3], atol=1e-12)


def test_every_euler_set_round_trips():
    angles = np.array([[0.3, 0.7, -1.1], [1.0, 0.2, 0.4]])
    sets = rotations.euler_sets()
    assert len(sets) == 12 and "3-1-3" in sets
    for s in sets:
        m = rotations.euler_to_matrix(angles, s)
        assert m.shape == (2, 3, 3)
        a = rotations.matrix_to_euler(m, s)
        np.testing.assert_allclose(rotations.euler_to_matrix(a, s), m, atol=1e-12)


def test_report_equals_cli(cli):
    values = [0.5, 0.7, -1.2]
    ours = rotations.report(values, "euler:3-1-3")
    theirs = cli("rotation", "--from", "euler:3-1-3", "--values", ",".join(repr(v) for v in values))
    assert ours == theirs


@pytest.mark.parametrize(
    "values, from_, message",
    [
        ([0.0, 0.0, 0.0, 1.0], "axis-angle", "axis"),
        ([0.0, 0.0, 0.0, 0.0], "quaternion", "quaternion"),
        ([[1.0, 0, 0], [0, 1, 0], [0, 0, -1]], "matrix", "rotation"),
        ([1.0, 2.0], "axis-angle", "shape"),
        ([1.0, 2.0, 3.0], "euler:1-1-2", "1-1-2"),
        ([1.0, 2.0, 3.0], "polar", "polar"),
        ([1.0, float("nan"), 3.0], "euler:3-1-3", "Euler angles"),
    ],
)
def test_bad_input_is_a_value_error(values, from_, message):
    with pytest.raises(ValueError, match=message):
        rotations.convert(values, from_, "matrix")


def test_report_bad_input():
    with pytest.raises(ValueError):
        rotations.report([1.0, 2.0], "quaternion")
