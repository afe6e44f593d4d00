"""Robot.jacobian(Q) and Robot.singular(Q) for Q of shape (N, n) (docs/python.md, "Jacobians and singularities of
many configurations"): every row equals the single form to rounding on every bundled robot and the 4-joint bench
arm, the batch holds computeJacobiansBatch's numbers, refusals name the row, out= as fk's.

Rounding bound (tests/common/jacobian_batch_check.hpp derives it): both forms evaluate the same chain product with
the same constants in another order of operations (SIMD lanes), n links each adding a few eps to the frames, so an
entry differs by at most 64 n eps times its column's scale: |scale_i| (|turn_i| R + |slide_i|) for the linear rows
and |scale_i turn_i| for the angular ones (R: the configuration's length scale, here bounded by 2 L + |p_tool|).
This file bounds every entry by the largest column scale, 64 n eps (R + 1) max|scale|: looser per entry, the same
order."""
import glob
import os

import numpy as np
import pytest

import lowpair

ROOT = os.environ.get("LOWPAIR_SOURCE_DIR", os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))
ROBOTS = sorted(glob.glob(os.path.join(ROOT, "models", "*.yaml"))) + [
    os.path.join(ROOT, "tests", "data", "bench", "rrpr_arm.yaml")]
EPS = np.finfo(float).eps


def configurations(robot, count, seed):
    # within every bundled robot's joint ranges (the tightest, puma's joint 3, ends at 0.785 rad)
    return np.random.default_rng(seed).uniform(-0.7, 0.7, (count, robot.dof))


@pytest.mark.parametrize("path", ROBOTS, ids=[os.path.basename(p) for p in ROBOTS])
def test_batched_jacobians_equal_single_rows_to_rounding(path):
    robot = lowpair.load(path)
    Q = configurations(robot, 37, 1)  # several 8-lane blocks, a partial one
    R = 2 * robot.length_scale + max(np.linalg.norm(robot.fk(q)[:3, 3]) for q in Q)
    for frame in ("spatial", "body", "geometric"):
        batch = robot.jacobian(Q, frame=frame)
        single = np.array([robot.jacobian(q, frame=frame) for q in Q])
        assert batch.shape == (len(Q), 6, robot.dof) and batch.dtype == np.float64
        column = np.max(np.abs(single), axis=(0, 1))  # each column's size: scale times (R or 1)
        bound = 64 * robot.dof * EPS * (R + 1) * np.maximum(column / max(R, 1.0), 1.0)
        assert np.all(np.abs(batch - single) <= bound), (frame, np.max(np.abs(batch - single) / bound))


@pytest.mark.parametrize("path", ROBOTS, ids=[os.path.basename(p) for p in ROBOTS])
def test_batched_singular_rows_follow_the_single_rank_rule(path):
    robot = lowpair.load(path)
    Q = configurations(robot, 9, 2)
    Q[4] = 0.0  # the zero configuration: singular for several of these arms (wrist or elbow aligned)
    batch = robot.singular(Q)
    assert len(batch) == len(Q) and batch.singular_values.shape == (len(Q), min(6, robot.dof))
    for k, q in enumerate(Q):
        one = robot.singular(q)
        # singular values to rounding (the Jacobians' bound, on a dimensionless Jacobian of entries <= ~2)
        assert np.allclose(batch.singular_values[k], one.singular_values, rtol=0, atol=1e3 * EPS), k
        # the rank and its consequences agree unless a singular value lies within rounding of the threshold
        near = np.min(np.abs(one.singular_values - one.tolerance)) <= 1e3 * EPS
        if not near:
            assert batch.rank[k] == one.rank and batch.singular[k] == one.singular, k
        assert batch.tolerance[k] == pytest.approx(one.tolerance, rel=1e-12)
        assert batch.sigma_min[k] == batch.singular_values[k, -1]
        assert batch.manipulability[k] == pytest.approx(one.manipulability, rel=1e-9, abs=1e3 * EPS)


def test_a_value_beyond_its_limit_is_named_with_its_row_and_out_is_left_as_it_was():
    robot = lowpair.load(os.path.join(ROOT, "models", "stanford_corke.yaml"))
    Q = np.tile(np.array([0.1, 0.2, 0.5, 0.0, 0.3, 0.0]), (300, 1))
    Q[200, 2] = 1e300  # in the second chunk
    out = np.full((300, 6, 6), 7.0)
    for call in (lambda: robot.jacobian(Q), lambda: robot.singular(Q), lambda: robot.jacobian(Q, out=out)):
        with pytest.raises(lowpair.Error, match=r"q\[200, 2\]: '1e\+300' is beyond joint 3's limit"):
            call()
    assert np.all(out == 7.0)


def test_out_takes_the_result_and_may_share_q_memory():
    robot = lowpair.load(os.path.join(ROOT, "models", "puma560_corke.yaml"))
    Q = configurations(robot, 20, 3)
    expected = robot.jacobian(Q, frame="geometric")
    out = np.full((20, 6, 6), 7.0)
    assert robot.jacobian(Q, frame="geometric", out=out) is out and np.array_equal(out, expected)
    # q stored inside the output buffer: read before it is overwritten (numpy's rule for overlapping out=)
    buf = np.zeros((20, 6, 6))
    buf.reshape(-1)[: Q.size] = Q.reshape(-1)
    q_view = buf.reshape(-1)[: Q.size].reshape(20, 6)
    robot.jacobian(q_view, frame="geometric", out=buf)
    assert np.array_equal(buf, expected)
    with pytest.raises(lowpair.Error, match=r"^out: expected a writeable C-contiguous float64 array of shape "
                                            r"\(20, 6, 6\), got a C-contiguous float64 array of shape \(20, 6, 5\)"):
        robot.jacobian(Q, out=np.zeros((20, 6, 5)))
    single = np.zeros((6, 6))
    assert robot.jacobian(Q[0], out=single) is single and np.array_equal(single, robot.jacobian(Q[0]))
