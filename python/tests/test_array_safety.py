"""Arrays the module writes into or sizes from: out= sharing memory with q, a refusal that leaves out= as it was, an
empty target list, and row counts beyond the CLI's limit (docs/python.md "Arrays")."""
import re

import numpy as np
import pytest

import lowpair
from test_kinematics import random_q

PUMA = "models/puma560_corke.yaml"
ROW_LIMIT = 1_000_000  # io::kMaxMeasurements, the CLI's rows per file


@pytest.fixture(scope="module")
def puma():
    return lowpair.load(PUMA)


@pytest.mark.parametrize("where", ["start", "end"])
def test_fk_into_out_that_holds_q_equals_fk_of_a_copy(puma, where):
    # q lives inside out's own buffer: results written over joint values not yet read must not be read back
    count = 1000
    q = random_q(puma, count, seed=5)
    expected = puma.fk(q.copy())
    buf = np.zeros((count, 4, 4))
    flat = buf.reshape(-1)
    view = (flat[:count * 6] if where == "start" else flat[-count * 6:]).reshape(count, 6)
    view[:] = q
    assert np.shares_memory(view, buf)
    result = puma.fk(view, out=buf)
    assert result is buf
    # the same kernel on the same joint values: bit for bit
    assert np.array_equal(buf, expected)


def test_fk_refusal_leaves_out_as_it_was(puma):
    count = 1000
    q = random_q(puma, count, seed=6)
    q[900, 2] = np.nan
    buf = np.full((count, 4, 4), 7.0)
    with pytest.raises(lowpair.Error, match=r"q\[900, 2\]: 'nan' is not finite"):
        puma.fk(q, out=buf)
    assert np.all(buf == 7.0)


def test_simulate_with_an_empty_target_list_is_refused(tmp_path):
    path = tmp_path / "smr.yaml"
    path.write_text(open(PUMA).read() + "targets:\n  - {name: smr_a, point: [0.01, 0, 0]}\n")
    robot = lowpair.load(str(path))
    with pytest.raises(lowpair.Error, match=r"^targets: is empty"):
        lowpair.simulate(robot, poses=3, measure="targets", targets=[])
    # the same robot with its file's targets: rows, and q of shape (rows, n)
    sim = lowpair.simulate(robot, poses=3, measure="targets")
    assert sim.q.shape == (3, 6)


def test_ik_and_compensate_refuse_rows_beyond_the_cli_limit(puma):
    # broadcast views: no memory behind the rows, so the refusal must come before any per-row work or allocation
    targets = np.broadcast_to(np.array([0.3, 0.1, 0.2]), (ROW_LIMIT + 1, 3))
    with pytest.raises(lowpair.Error, match=rf"^targets: {ROW_LIMIT + 1} rows, more than the {ROW_LIMIT}"):
        lowpair.ik(puma, targets)
    q = np.broadcast_to(np.zeros(6), (10 * ROW_LIMIT, 6))
    with pytest.raises(lowpair.Error, match=rf"^q: {10 * ROW_LIMIT} rows, more than the {ROW_LIMIT}"):
        lowpair.compensate(puma, puma, q)


def test_ik_rows_json_is_built_when_asked(puma):
    q = random_q(puma, 4, seed=7)
    T = puma.fk(q)
    solutions = lowpair.ik(puma, T[:, :3, 3].copy(), q0=q)
    rows = solutions.to_dict()["rows"]
    assert [row["line"] for row in rows] == [0, 1, 2, 3]
    assert all(row["seed"] == "file" for row in rows)
    assert all("seed" not in row for row in lowpair.compensate(puma, puma, q).to_dict()["rows"])


def test_version_is_the_packages():
    # lowpair/version.hpp, generated from the CMake project version (the CLI's --version reads it too)
    import re
    cmake = open("CMakeLists.txt").read()
    assert lowpair.__version__ == re.search(r"project\(lowpair VERSION (\d+\.\d+\.\d+)", cmake).group(1)


def test_load_takes_a_pathlike_and_names_other_types():
    import pathlib
    assert lowpair.load(pathlib.Path(PUMA)).name == lowpair.load(PUMA).name
    with pytest.raises(lowpair.Error, match=r"^path: expected a str or os.PathLike, got int"):
        lowpair.load(3)


def test_ik_takes_one_4x4_pose_as_a_batch_of_one(puma):
    q = random_q(puma, 1, seed=8)
    T = puma.fk(q[0], model="poe")
    one, batch = lowpair.ik(puma, T, q0=q[0]), lowpair.ik(puma, T[None], q0=q[0])
    assert len(one) == 1 and one.to_dict() == batch.to_dict()
    # a transposed view reads through its strides: the same transform
    assert lowpair.ik(puma, np.ascontiguousarray(T.T).T, q0=q[0]).to_dict() == one.to_dict()


@pytest.mark.parametrize("buf,what", [(np.zeros((10, 4, 4), dtype=np.float32), "C-contiguous float32"),
                                      (np.zeros((10, 4, 4), order="F"), "Fortran-ordered float64"),
                                      (np.zeros((10, 4, 4))[:, :, ::-1], "non-contiguous float64")])
def test_out_of_the_wrong_kind_names_what_differs(puma, buf, what):
    with pytest.raises(lowpair.Error, match=f"got a {what} array of shape \\(10, 4, 4\\)"):
        puma.fk(random_q(puma, 10, seed=9), out=buf)
    ro = np.zeros((10, 4, 4))
    ro.setflags(write=False)
    with pytest.raises(lowpair.Error, match="got a read-only C-contiguous float64 array"):
        puma.fk(random_q(puma, 10, seed=9), out=ro)


STANFORD = "models/stanford_corke.yaml"  # joint 3 prismatic (metres)
LIMIT = r"'1e\+300' is beyond joint 3's limit \(j3, prismatic: \|scale \(q \+ offset\)\| at most 1e100"


def test_joint_values_beyond_their_limits_are_refused_naming_the_index():
    # a slide of 1e300 gave inf/nan from fk, jacobian, ik and compensate, and simulate wrote a CSV its reader
    # refuses; the bound is the one the model's range ends obey (|scale (q + offset)| <= 1e100)
    robot = lowpair.load(STANFORD)
    q = np.array([0.1, 0.2, 1e300, 0.0, 0.3, 0.0])
    for call in (robot.fk, robot.jacobian, robot.singular):
        with pytest.raises(lowpair.Error, match=r"stanford_corke.yaml: q\[2\]: " + LIMIT):
            call(q)
    Q = np.tile(np.array([0.1, 0.2, 0.5, 0.0, 0.3, 0.0]), (600, 1))
    Q[300, 2] = 1e300  # the second chunk of the batch (256 rows each)
    buf = np.full((600, 4, 4), 7.0)
    for out in (None, buf):
        with pytest.raises(lowpair.Error, match=r"q\[300, 2\]: " + LIMIT):
            robot.fk(Q, out=out)
    assert np.all(buf == 7.0)
    with pytest.raises(lowpair.Error, match=r"q0\[2\]: " + LIMIT):
        lowpair.ik(robot, np.array([[0.3, 0.2, 0.5]]), q0=q)
    with pytest.raises(lowpair.Error, match=r"q\[0, 2\]: " + LIMIT):
        lowpair.compensate(robot, robot, q[None, :])
    with pytest.raises(lowpair.Error, match=r"q\[1, 0\]: '1e\+200' is beyond joint 1's limit \(j1, revolute"):
        lowpair.simulate(robot, q=np.array([[0.1, 0.2, 0.5, 0, 0, 0], [1e200, 0.2, 0.5, 0, 0, 0]]))
    # at the limit every result is finite
    edge = q.copy()
    edge[2] = 1e100
    assert np.all(np.isfinite(robot.fk(edge))) and np.all(np.isfinite(robot.jacobian(edge)))
    assert np.all(np.isfinite(robot.fk(np.tile(edge, (300, 1)))))


@pytest.mark.parametrize("dtype", ["complex128", "complex64", "datetime64[s]", "timedelta64[ms]"])
def test_arrays_that_are_not_real_numbers_are_refused_naming_argument_and_dtype(puma, dtype):
    # complex lost its imaginary part with only numpy's ComplexWarning; datetime64 was read as numbers
    bad = np.zeros(6, dtype=dtype)
    want = rf"q: expected real numbers, got an array of dtype {re.escape(str(bad.dtype))}"
    for call in (puma.fk, puma.jacobian, puma.singular):
        with pytest.raises(lowpair.Error, match=rf"^{PUMA}: {want}"):
            call(bad)
    with pytest.raises(lowpair.Error, match=rf"^{PUMA}: {want}"):
        lowpair.simulate(puma, q=bad[None, :])
    with pytest.raises(lowpair.Error, match=rf"^{want}"):
        lowpair.compensate(puma, puma, bad[None, :])
    with pytest.raises(lowpair.Error, match=rf"^targets: expected real numbers, got an array of dtype"):
        lowpair.ik(puma, np.zeros((2, 3), dtype=dtype))
    with pytest.raises(lowpair.Error, match=rf"^positions: expected real numbers, got an array of dtype"):
        lowpair.calibrate(puma, np.zeros((8, 6)), np.zeros((8, 3), dtype=dtype))
    # lists are read as numpy reads them
    if dtype.startswith("complex"):
        with pytest.raises(lowpair.Error, match="imaginary part would be dropped"):
            puma.jacobian([0j] * 6)
    # integers and bools are numbers (as before)
    assert np.array_equal(puma.fk(np.zeros(6, dtype=int)), puma.fk(np.zeros(6)))


def test_a_broadcast_view_beyond_the_row_limit_is_refused_before_any_copy(puma):
    # (1e9, 6) of one row: numpy would copy 48 GB (MemoryError, or the TypeError of a failed conversion)
    view = np.broadcast_to(np.zeros(6), (10**9, 6))
    limit = rf"q: {10**9} rows, more than the {ROW_LIMIT} one call takes \(the CLI's limit\): split the array"
    for call in (puma.fk, lambda q: lowpair.simulate(puma, q=q),
                 lambda q: lowpair.calibrate(puma, q, np.zeros((3, 3)))):
        with pytest.raises(lowpair.Error, match=rf"^{PUMA}: {limit}$"):
            call(view)


def test_a_huge_string_argument_is_cut_in_the_message(puma):
    # a megabyte of text was echoed whole; quoted as a file's text is: 40 bytes, then "..."
    big = "x" * 1_000_000
    quoted = "'" + "x" * 40 + "...'"
    m = lowpair.simulate(puma, poses=8, seed=1)
    calls = [
        (lambda: puma.fk(np.zeros(6), model=big), "model"),
        (lambda: puma.jacobian(np.zeros(6), frame=big), "frame"),
        (lambda: lowpair.load("models/panda.xml", tip=big), "tip"),
        (lambda: lowpair.load("models/puma560_okamura_nominal.urdf", tip=big), "tip"),
        (lambda: lowpair.load("models/panda.xml", tip="tool", base=big), "base"),
        (lambda: lowpair.simulate(puma, poses=3, measure=big), "measure"),
        (lambda: lowpair.calibrate(puma, m.q, m.positions, m.rotations, loss=big), "loss"),
        (lambda: lowpair.calibrate(puma, m.q, m.positions, m.rotations, select=big), "select"),
        (lambda: lowpair.calibrate(puma, m.q, m.positions, m.rotations, parameters=big), "parameters"),
        (lambda: lowpair.calibrate(puma, m.q, m.positions, m.rotations, parameters=big + ",,x"), "parameters"),
        (lambda: lowpair.compensate(puma, puma, m.q, measure=big), "measure"),
        (lambda: lowpair.plan(puma, poses=3, criterion=big), "criterion"),
        (lambda: lowpair.export(puma, "unused.urdf", format=big), "format"),
    ]
    for call, name in calls:
        with pytest.raises(lowpair.Error) as info:
            call()
        text = str(info.value)
        assert quoted in text and len(text) < 1000, (name, text[:300])
