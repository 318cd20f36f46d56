"""Hostile inputs end in pkm.Error (with a key path for a study) or in the documented mask,
never in a crash, a hang or a silent NaN."""

import numpy as np
import pytest

import pkm


@pytest.fixture(scope="module")
def tsai():
    return pkm.Mechanism("tsai")


POINTS = np.array([[0.0, 0.0, 0.5], [0.1, -0.1, 0.6], [0.0, 0.0, 3.0]])


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_coordinates_are_refused_with_their_row(tsai, bad):
    x = POINTS.copy()
    x[1, 2] = bad
    with pytest.raises(pkm.InvalidInput, match=r"points\[1, 2\]"):
        tsai.inverse_kinematics(x)
    with pytest.raises(pkm.InvalidInput, match=r"guess\[1, 2\]"):
        tsai.forward_kinematics(np.zeros((3, 3)), x)


@pytest.mark.parametrize("shape", [(3,), (4, 2), (2, 4), (2, 3, 1), ()])
def test_wrong_shapes_are_refused(tsai, shape):
    with pytest.raises(pkm.InvalidInput, match="N × 3"):
        tsai.local_indices(np.zeros(shape))


def test_other_real_dtypes_are_converted(tsai):
    reference = tsai.inverse_kinematics(POINTS)
    for dtype in [np.float32, ">f8"]:
        q, ok = tsai.inverse_kinematics(POINTS.astype(dtype))
        expected = tsai.inverse_kinematics(POINTS.astype(dtype).astype(np.float64))
        np.testing.assert_array_equal(q, expected[0])
        np.testing.assert_array_equal(ok, reference[1])
    q, _ = tsai.inverse_kinematics(np.zeros((2, 3), dtype=np.int32))
    np.testing.assert_array_equal(q, tsai.inverse_kinematics(np.zeros((2, 3)))[0])
    q, _ = tsai.inverse_kinematics(POINTS.tolist())
    np.testing.assert_array_equal(q, reference[0])


@pytest.mark.parametrize("value", [POINTS.astype(complex), POINTS.astype(str), POINTS.astype(object), "abc", None, [[1, 2], [3]]])
def test_non_real_inputs_are_refused(tsai, value):
    with pytest.raises(pkm.InvalidInput):
        tsai.inverse_kinematics(value)


def test_non_contiguous_arrays_give_the_contiguous_results(tsai):
    big = np.zeros((6, 5))
    big[::2, 1:4] = POINTS
    strided = big[::2, 1:4]
    fortran = np.asfortranarray(POINTS)
    transposed = np.ascontiguousarray(POINTS.T).T
    expected = tsai.velocity_jacobian(POINTS)
    for view in [strided, fortran, transposed]:
        assert not view.flags.c_contiguous
        got = tsai.velocity_jacobian(view)
        np.testing.assert_array_equal(got[0], expected[0])
        np.testing.assert_array_equal(got[1], expected[1])


def test_empty_arrays_give_empty_results(tsai):
    q, ok = tsai.inverse_kinematics(np.zeros((0, 3)))
    assert q.shape == (0, 3) and ok.shape == (0,)
    j, _ = tsai.velocity_jacobian(np.zeros((0, 3)))
    assert j.shape == (0, 3, 3)
    assert tsai.contains(np.zeros((0, 3))).shape == (0,)


def test_huge_inputs_are_refused_before_anything_is_allocated(tsai):
    # A broadcast view: (MAX_POINTS + 1) × 3 rows that take no memory.
    huge = np.broadcast_to(np.zeros(3), (pkm.MAX_POINTS + 1, 3))
    with pytest.raises(pkm.InvalidInput, match="at most"):
        tsai.velocity_jacobian(huge)
    huge_int = np.broadcast_to(np.zeros(3, dtype=np.int64), (10**12, 3))
    with pytest.raises(pkm.InvalidInput, match="at most"):
        tsai.inverse_kinematics(huge_int)


def test_unreachable_points_are_masked_not_raised(tsai):
    q, ok = tsai.inverse_kinematics(POINTS)
    assert ok.tolist() == [True, True, False]
    assert np.isnan(q[2]).all()


@pytest.mark.parametrize(
    "design, constraints, path",
    [
        ({"rotary_delta": {"base_radius": 0.15, "plate_offset": 0.04, "arm": -0.2, "forearm": 0.45}}, None, "mechanism.rotary_delta.arm"),
        ({"rotary_delta": {"base_radius": 0.15, "plate_offset": 0.04, "arms": 0.2, "forearm": 0.45}}, None, "mechanism.rotary_delta"),
        ({"tsai": {"a": "long", "b": 0.3}}, None, "mechanism.tsai.a"),
        ({"tsai": {"a": 0.2, "b": 0.3}}, {"joint_range": [0.0, 1.0]}, "constraints"),
        ({"tsai": {"a": 0.2, "b": 0.3}}, {"joint_range_deg": [10.0, -10.0]}, "constraints"),
    ],
)
def test_bad_designs_raise_with_their_key_path(design, constraints, path):
    with pytest.raises(pkm.InvalidInput) as caught:
        pkm.Mechanism(design, constraints)
    assert caught.value.key_path is not None
    assert caught.value.key_path.startswith(path), (caught.value.key_path, str(caught.value))


@pytest.mark.parametrize("design", ["no_such_robot", 42, [1, 2], {"tsai": {}, "three_upu": {}}, {}])
def test_unusable_designs_raise_invalid_input(design):
    with pytest.raises(pkm.InvalidInput):
        pkm.Mechanism(design)


def test_forward_kinematics_rows_must_match(tsai):
    with pytest.raises(pkm.InvalidInput, match="rows"):
        tsai.forward_kinematics(np.zeros((3, 3)), np.zeros((2, 3)))
