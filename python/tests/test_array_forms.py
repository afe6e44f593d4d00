"""Every input form a numpy user passes, to every public function taking an array (issue 30; docs/python.md
"Arrays"): one table of array arguments (SLOTS), one accepted test (each form gives the float64 C-contiguous
array's result, bit for bit unless a rounding is documented) and one refused test (lowpair.Error naming the
argument and what was expected and given), plus the single-row / batch-of-one and os.PathLike forms.

Accepted: float64 C order, Fortran order, strided, negative-stride, unaligned and big-endian views, nested lists,
longdouble, float32 (converted exactly: the result is the float64 of the float32 values'; ik's rotations are
taken as the nearest rotation, docs/python.md), integers and bools (0/1 as numbers). Refused: complex,
datetime64, object and text arrays (before any conversion, naming the dtype), NaN and inf, a wrong shape or
joint count, 3-D where 2-D is expected, and empty arrays where rows are needed (simulate, calibrate)."""
# Tests that need the bindings' fixes of this change built (python/src/common.cpp, robot.cpp, ik.cpp, files.cpp):
# test_refused_forms_name_the_argument[*-str, *-object] (text and object arrays refused), [with_targets.point-*]
# (complex/datetime64 refused, the given shape named), [transformed.T-*nan/inf] and [simulate.frame(4,4)-*nan/inf]
# (the index named), [ik.rotations(N,3,3)-*nan/inf] (rotations named); test_zero_rows_give_an_empty_result[ik.*,
# compensate.q] ((0, n)); test_a_path_is_a_str_or_an_os_pathlike[all but load].
import math
import re
import warnings
from dataclasses import dataclass, field
from typing import Callable, List, Optional, Tuple

import numpy as np
import pytest

import lowpair

PUMA = "models/puma560_corke.yaml"   # 6 revolute joints, metres, ranges
ELBOW = "models/elbow_mls.yaml"      # 6 revolute joints, no ranges (compensate's second robot)
EPS = np.finfo(float).eps

puma = lowpair.load(PUMA)
elbow = lowpair.load(ELBOW)

# ----- the reference values (float64) ------------------------------------------------------------------------

Q1 = np.array([0.1, -0.4, 0.3, 0.2, 0.5, -0.1])
QN = np.array([Q1, 0.5 * Q1, -0.3 * Q1])
SIM = lowpair.simulate(puma, poses=12, seed=1)   # pose measurements: q (12, 6), positions, rotations
TN = puma.fk(QN, model="poe")                    # (3, 4, 4) reachable poses
RN = TN[:, :3, :3].copy()                        # (3, 3, 3) rotation matrices
WN = SIM.rotations[:3].copy()                    # (3, 4) unit quaternions
T1 = puma.fk(-0.7 * Q1)                          # a rigid motion whose rotation float32 rounds
FRAME6 = np.array([0.3, -1.2, 2.0, 3.0, -0.8, 0.4])

# 0/1 values valid for each argument (the int and bool forms): joint 3 kept at 0 (its range ends at 0.785)
rng = np.random.default_rng(30)
Q01_1 = np.array([1.0, 1.0, 0.0, 0.0, 1.0, 0.0])
Q01_N = rng.integers(0, 2, size=(3, 6)).astype(float)
Q01_N[:, 2] = 0.0
Q01_12 = rng.integers(0, 2, size=(12, 6)).astype(float)
Q01_12[:, 2] = 0.0
PERM = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])   # a rotation of 0s and 1s (det +1)
R01_N = np.array([np.eye(3), PERM, PERM @ PERM])
T01 = np.eye(4)
T01[:3, :3], T01[:3, 3] = PERM, [1.0, 0.0, 1.0]
T01_N = np.array([T01, np.eye(4), T01])
W01_N = np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0], [0, 0, 0, 1.0]])
W01_12 = np.tile(W01_N, (4, 1))
P01_N = np.array([[1.0, 0, 0], [0, 1.0, 1.0], [0, 0, 1.0]])
P01_12 = rng.integers(0, 2, size=(12, 3)).astype(float)


def quiet(f):
    """calibrate's range warnings (UserWarning) are not what is tested here."""
    def call(*args):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)
            return f(*args)
    return call


def ik_result(sol):
    return {"q": sol.q, "status": sol.status, "iterations": sol.iterations, "position_error": sol.position_error,
            "rotation_error": sol.rotation_error, "dict": sol.to_dict()}


def cal_result(cal):
    d = cal.to_dict()
    d.pop("seconds", None)  # the fit's run time
    return d


def singular_rows(s):
    return {key: getattr(s, key) for key in ("rank", "singular", "sigma_min", "manipulability", "condition",
                                             "tolerance", "singular_values")}


def sim_result(m):
    return {"q": m.q, "positions": m.positions, "rotations": m.rotations}


@dataclass
class Slot:
    """One array argument of one function: `call(value)` with every other argument fixed."""
    name: str                   # test id: function.argument
    arg: str                    # the argument's name, as the message must name it
    call: Callable              # value -> a result comparable with same()
    ref: np.ndarray             # float64 values the call accepts
    ref01: np.ndarray           # 0/1 values it accepts (int and bool forms)
    nonfinite: str              # regex of the NaN message after the argument's name
    shapes: List[Tuple[str, Callable, str]] = field(default_factory=list)  # (id, ref -> bad value, given shape)
    f32: str = "exact"          # 'exact': float32 converted exactly; 'round': to the documented rounding;
    #                             'xfail:REASON': refused today against the docs
    empty_ok: bool = False      # zero rows give an empty result (else refused)
    empty: Optional[Callable] = None  # ref -> its empty form


def _drop_col(x):
    return x[..., :-1]


def _three_d(x):
    return x[None] if x.ndim >= 2 else x[None, None]


SHAPE_3D = ("3-D", _three_d, None)       # the given shape is the builder's
WRONG_COUNT = ("wrong count", _drop_col, None)

SLOTS = [
    Slot("fk.q", "q", lambda a: puma.fk(a), Q1, Q01_1, r"\[1\]: '-?(nan|inf)' is not finite",
         [WRONG_COUNT, SHAPE_3D]),
    Slot("fk.Q", "q", lambda a: puma.fk(a), QN, Q01_N, r"\[0, 1\]: '-?(nan|inf)' is not finite",
         [WRONG_COUNT, SHAPE_3D], empty_ok=True),
    Slot("fk.Q(dh)", "q", lambda a: puma.fk(a, model="dh"), QN, Q01_N, r"\[0, 1\]: '-?(nan|inf)' is not finite",
         [WRONG_COUNT, SHAPE_3D], empty_ok=True),
    Slot("jacobian.q", "q", lambda a: puma.jacobian(a, frame="geometric"), Q1, Q01_1,
         r"\[1\]: '-?(nan|inf)' is not finite", [WRONG_COUNT, SHAPE_3D]),
    Slot("jacobian.Q", "q", lambda a: puma.jacobian(a, frame="body"), QN, Q01_N,
         r"\[0, 1\]: '-?(nan|inf)' is not finite", [WRONG_COUNT, SHAPE_3D], empty_ok=True),
    Slot("singular.q", "q", lambda a: puma.singular(a).to_dict(), Q1, Q01_1, r"\[1\]: '-?(nan|inf)' is not finite",
         [WRONG_COUNT, SHAPE_3D]),
    Slot("singular.Q", "q", lambda a: singular_rows(puma.singular(a)), QN, Q01_N,
         r"\[0, 1\]: '-?(nan|inf)' is not finite", [WRONG_COUNT, SHAPE_3D], empty_ok=True),
    Slot("transformed.T", "T", lambda a: puma.transformed(a).fk(QN), T1, T01, r"\[0, 1\]: '-?(nan|inf)' is not finite",
         [("(4, 3)", _drop_col, None), SHAPE_3D, ("(16,)", lambda x: x.reshape(-1), None)],
         f32="round"),
    Slot("with_targets.point", "targets", lambda a: puma.with_targets({"smr": a}).targets["smr"],
         np.array([0.01, -0.02, 0.05]), np.array([1.0, 0.0, 1.0]), r"target smr: the point is not finite",
         [("(2,)", _drop_col, None), ("(1, 3)", lambda x: x[None], None)]),
    Slot("ik.targets(N,4,4)", "targets", lambda a: ik_result(lowpair.ik(puma, a, q0=Q1)), TN, T01_N,
         r"\[0\]: not finite", [("(N, 4, 3)", _drop_col, None), ("(1, N, 4, 4)", lambda x: x[None], None)],
         f32="round", empty_ok=True),
    Slot("ik.targets(N,3)", "targets", lambda a: ik_result(lowpair.ik(puma, a, q0=Q1)), TN[:, :3, 3].copy(), P01_N,
         r"\[0\]: not finite", [("(N, 2)", _drop_col, None), SHAPE_3D, ("(3,)", lambda x: x[0], None)],
         empty_ok=True),
    Slot("ik.rotations(N,4)", "rotations",
         lambda a: ik_result(lowpair.ik(puma, TN[:, :3, 3].copy(), rotations=a, q0=Q1)), WN, W01_N,
         r"row 0: qw\.\.qz is not a unit quaternion \(norm (nan|inf)\)",
         [("(N, 3)", _drop_col, None), SHAPE_3D, ("(4,)", lambda x: x[0], None)], f32="round"),
    Slot("ik.rotations(N,3,3)", "rotations",
         lambda a: ik_result(lowpair.ik(puma, TN[:, :3, 3].copy(), rotations=a, q0=Q1)), RN, R01_N,
         r"\[0, 0, 1\]: '-?(nan|inf)' is not finite",
         [("(N, 3, 2)", _drop_col, None), ("(1, N, 3, 3)", lambda x: x[None], None)], f32="round"),
    Slot("ik.q0", "q0", lambda a: ik_result(lowpair.ik(puma, TN, q0=a)), QN, Q01_N,
         r"\[0, 1\]: '-?(nan|inf)' is not finite", [WRONG_COUNT, SHAPE_3D, ("rows != targets", lambda x: x[:2], None)]),
    Slot("compensate.q", "q", lambda a: ik_result(lowpair.compensate(puma, elbow, a)), QN, Q01_N,
         r"\[0, 1\]: '-?(nan|inf)' is not finite", [WRONG_COUNT, SHAPE_3D], empty_ok=True),
    Slot("simulate.q", "q", lambda a: sim_result(lowpair.simulate(puma, q=a)), QN, Q01_N,
         r"\[0, 1\]: '-?(nan|inf)' is not finite", [WRONG_COUNT, SHAPE_3D, ("(6,)", lambda x: x[0], None)]),
    Slot("simulate.frame(6,)", "frame", lambda a: sim_result(lowpair.simulate(puma, q=QN, frame=a)), FRAME6,
         np.array([0.0, 1.0, 0.0, 1.0, 1.0, 0.0]), r"'-?(nan|inf)' is not finite",
         [("(5,)", _drop_col, None), ("(1, 6)", lambda x: x[None], None), ("(1, 1, 6)", lambda x: x[None, None], None)]),
    Slot("simulate.frame(4,4)", "frame", lambda a: sim_result(lowpair.simulate(puma, q=QN, frame=a)), T1, T01,
         r"\[0, 1\]: '-?(nan|inf)' is not finite", [("(4, 3)", _drop_col, None), SHAPE_3D],
         f32="round"),
    Slot("calibrate.q", "q", quiet(lambda a: cal_result(lowpair.calibrate(puma, a, SIM.positions, SIM.rotations))),
         SIM.q, Q01_12, r"\[0, 1\]: '-?(nan|inf)' is not finite",
         [WRONG_COUNT, SHAPE_3D, ("(6,)", lambda x: x[0], None)]),
    Slot("calibrate.positions", "positions",
         quiet(lambda a: cal_result(lowpair.calibrate(puma, SIM.q, a, SIM.rotations))), SIM.positions, P01_12,
         r"\[0, 1\]: '-?(nan|inf)' is not finite",
         [("(N, 2)", _drop_col, None), SHAPE_3D, ("rows != q's", lambda x: x[:-1], None)]),
    Slot("calibrate.rotations", "rotations",
         quiet(lambda a: cal_result(lowpair.calibrate(puma, SIM.q, SIM.positions, a))), SIM.rotations, W01_12,
         r"row 0: qw\.\.qz is not a unit quaternion \(norm (nan|inf)\)",
         [("(N, 3)", _drop_col, None), SHAPE_3D, ("rows != q's", lambda x: x[:-1], None)]),
    Slot("calibrate.validation_q", "validation_q",
         quiet(lambda a: cal_result(lowpair.calibrate(puma, SIM.q, SIM.positions, SIM.rotations, validation_q=a,
                                                      validation_positions=SIM.positions,
                                                      validation_rotations=SIM.rotations))),
         SIM.q, Q01_12, r"\[0, 1\]: '-?(nan|inf)' is not finite", [WRONG_COUNT, SHAPE_3D]),
    Slot("calibrate.validation_positions", "validation_positions",
         quiet(lambda a: cal_result(lowpair.calibrate(puma, SIM.q, SIM.positions, SIM.rotations, validation_q=SIM.q,
                                                      validation_positions=a,
                                                      validation_rotations=SIM.rotations))),
         SIM.positions, P01_12, r"\[0, 1\]: '-?(nan|inf)' is not finite", [("(N, 2)", _drop_col, None), SHAPE_3D]),
    Slot("calibrate.validation_rotations", "validation_rotations",
         quiet(lambda a: cal_result(lowpair.calibrate(puma, SIM.q, SIM.positions, SIM.rotations, validation_q=SIM.q,
                                                      validation_positions=SIM.positions,
                                                      validation_rotations=a))),
         SIM.rotations, W01_12, r"row 0: qw\.\.qz is not a unit quaternion \(norm (nan|inf)\)",
         [("(N, 3)", _drop_col, None), SHAPE_3D]),
]
SLOT_IDS = [s.name for s in SLOTS]
assert len(set(SLOT_IDS)) == len(SLOT_IDS)

# ----- comparison --------------------------------------------------------------------------------------------


def same(a, b, rtol=0.0, atol=0.0, path="result"):
    """Bit for bit (NaN equal to NaN), or within rtol/atol for floats when given; strings and ints exactly."""
    if isinstance(a, dict):
        assert isinstance(b, dict) and a.keys() == b.keys(), path
        for k in a:
            same(a[k], b[k], rtol, atol, f"{path}[{k!r}]")
    elif isinstance(a, (list, tuple)):
        assert isinstance(b, (list, tuple)) and len(a) == len(b), path
        for k, (x, y) in enumerate(zip(a, b)):
            same(x, y, rtol, atol, f"{path}[{k}]")
    elif isinstance(a, np.ndarray) or isinstance(a, float):
        a, b = np.asarray(a), np.asarray(b)
        assert a.shape == b.shape and a.dtype == b.dtype, (path, a.shape, b.shape, a.dtype, b.dtype)
        if a.dtype.kind == "f" and (rtol or atol):
            assert np.allclose(a, b, rtol=rtol, atol=atol, equal_nan=True), (path, np.max(np.abs(a - b)))
        else:
            assert np.array_equal(a, b, equal_nan=a.dtype.kind == "f"), path
    elif isinstance(a, str) and (rtol or atol):
        pass  # a row's reason quotes its numbers (to rounding here)
    else:
        assert a == b, (path, a, b)


# ----- the accepted forms ------------------------------------------------------------------------------------


def _strided(x):
    wide = np.repeat(x, 2, axis=-1)
    v = wide[..., ::2]
    assert not v.flags.c_contiguous
    return v


def _negative(x):
    v = np.flip(np.flip(x, 0).copy(), 0)
    assert v.strides[0] < 0 or x.shape[0] <= 1
    return v


def _unaligned(x):
    raw = np.frombuffer(b"\0" + np.ascontiguousarray(x).tobytes(), dtype=np.float64, offset=1).reshape(x.shape)
    assert not raw.flags.aligned
    return raw


# (id, builder, uses ref01): each gives the same numbers as its float64 C-contiguous reference
FORMS = [
    ("float64-C", lambda x: np.ascontiguousarray(x), False),
    ("fortran", lambda x: np.asfortranarray(x), False),
    ("strided", _strided, False),
    ("negative-stride", _negative, False),
    ("unaligned", _unaligned, False),
    ("big-endian", lambda x: x.astype(">f8"), False),
    ("list", lambda x: x.tolist(), False),
    ("longdouble", lambda x: x.astype(np.longdouble), False),
    ("int64", lambda x: x.astype(np.int64), True),
    ("int32", lambda x: x.astype(np.int32), True),
    ("uint8", lambda x: x.astype(np.uint8), True),
    ("int-list", lambda x: x.astype(int).tolist(), True),
    ("bool", lambda x: x.astype(bool), True),
]

_result_cache = {}


def reference(slot, ones):
    key = (slot.name, ones)
    if key not in _result_cache:
        _result_cache[key] = slot.call(np.ascontiguousarray(slot.ref01 if ones else slot.ref))
    return _result_cache[key]


@pytest.mark.parametrize("form,build,ones", FORMS, ids=[f[0] for f in FORMS])
@pytest.mark.parametrize("slot", SLOTS, ids=SLOT_IDS)
def test_accepted_forms_give_the_float64_result(slot, form, build, ones):
    x = slot.ref01 if ones else slot.ref
    if form == "fortran" and x.ndim < 2:
        pytest.skip("a vector has one order")
    same(slot.call(build(x)), reference(slot, ones))


def _float32_param(slot):
    marks = []
    if slot.f32.startswith("xfail:"):
        marks = [pytest.mark.xfail(strict=True, raises=lowpair.Error, reason=slot.f32[len("xfail:"):])]
    return pytest.param(slot, id=slot.name, marks=marks)


@pytest.mark.parametrize("slot", [_float32_param(s) for s in SLOTS])
def test_float32_is_converted(slot):
    """float32: the result of the float64 of the float32 values, bit for bit; a rotation (ik) to float32's rounding."""
    x32 = slot.ref.astype(np.float32)
    got = slot.call(x32)
    if slot.f32 == "exact":
        same(got, slot.call(x32.astype(np.float64)))
    else:
        # a rotation taken as the nearest rotation (docs/python.md; its float64 copy is refused as no rotation to
        # double precision): the float64 reference's result to float32 rounding
        want = reference(slot, False)
        if "iterations" in want:  # ik: the same solutions and statuses (the iteration counts may differ)
            got, want = ({k: v for k, v in r.items() if k not in ("iterations", "dict")} for r in (got, want))
        same(got, want, rtol=1e-5, atol=1e-5)


@pytest.mark.parametrize("slot", [s for s in SLOTS if s.empty_ok], ids=[s.name for s in SLOTS if s.empty_ok])
def test_zero_rows_give_an_empty_result(slot):
    empty = np.zeros((0,) + slot.ref.shape[1:])
    got = slot.call(empty)
    if isinstance(got, dict) and "q" in got:  # IkSolutions: q keeps its n columns
        assert got["q"].shape == (0, puma.dof) and got["status"] == []
    elif isinstance(got, dict):  # SingularityBatch: a row per configuration, singular values keep min(6, n)
        assert got["rank"].shape == (0,) and got["singular_values"].shape == (0, 6)
    elif slot.name.startswith("jacobian"):
        assert got.shape == (0, 6, puma.dof)
    else:
        assert got.shape == (0, 4, 4)


# ----- the refused forms -------------------------------------------------------------------------------------


def _shape(x):
    return "(" + ", ".join(str(d) for d in x.shape) + (",)" if x.ndim == 1 else ")")


def _with(x, value):
    y = np.array(x, dtype=float)
    y.reshape(-1)[1] = value
    return y


def refused_cases():
    cases = []
    for s in SLOTS:
        def add(label, build, pattern, marks=()):
            cases.append(pytest.param(s, build, pattern, id=f"{s.name}-{label}", marks=list(marks)))
        a = re.escape(s.arg)
        for dtype in ("complex128", "complex64", "datetime64[s]", "timedelta64[ms]"):
            add(dtype, lambda x, d=dtype: np.zeros(x.shape, dtype=d),
                rf"\b{a}\b.*expected real numbers, got an array of dtype {re.escape(str(np.dtype(dtype)))}")
        # text and objects were converted by numpy (float('0.1')): refused since the fix (python/src/common.cpp)
        add("str", lambda x: x.astype(str), rf"\b{a}\b.*expected real numbers, got an array of dtype <U\d+")
        add("object", lambda x: x.astype(object), rf"\b{a}\b.*expected real numbers, got an array of dtype object")
        nonfinite = rf"\b{a}(: )?{s.nonfinite}"  # the argument, then (its index and) the value
        add("nan", lambda x: _with(x, np.nan), nonfinite)
        add("inf", lambda x: _with(x, np.inf), nonfinite)
        add("-inf", lambda x: _with(x, -np.inf), nonfinite)
        for label, build, _ in s.shapes:
            add(label, build, None)
        if not s.empty_ok:
            add("empty rows" if s.ref.ndim >= 2 else "empty", lambda x: np.zeros((0,) + x.shape[1:]),
                rf"\b{a}\b.*(no measurements|no joint values|expected .*got (shape )?\(0,)")
    return cases


@pytest.mark.parametrize("slot,build,pattern", refused_cases())
def test_refused_forms_name_the_argument(slot, build, pattern):
    bad = build(slot.ref)
    if pattern is None:  # a shape: the message names the argument, what it expected and the shape given
        pattern = rf"\b{re.escape(slot.arg)}\b.*expected .*got (shape )?{re.escape(_shape(bad))}"
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # numpy's ComplexWarning would mean a conversion happened
        with pytest.raises(lowpair.Error, match=pattern):
            slot.call(bad)


# ----- a single row, a batch of one, a frame's two forms --------------------------------------------------------


def test_fk_single_row_and_batch_of_one_agree_to_the_documented_rounding():
    one, batch = puma.fk(Q1), puma.fk(Q1[None])
    assert batch.shape == (1, 4, 4)
    # docs/python.md "Batched FK": within 8 eps in the rotation and 36 eps L in the position
    assert np.max(np.abs(one[:3, :3] - batch[0, :3, :3])) <= 8 * EPS
    assert np.max(np.abs(one[:3, 3] - batch[0, :3, 3])) <= 36 * EPS * puma.length_scale
    assert np.array_equal(one[3], batch[0, 3])


def test_compensate_single_row_is_a_batch_of_one():
    same(ik_result(lowpair.compensate(puma, elbow, Q1)), ik_result(lowpair.compensate(puma, elbow, Q1[None])))


def test_ik_single_transform_and_single_seed_are_batches_of_one():
    same(ik_result(lowpair.ik(puma, TN[0], q0=Q1)), ik_result(lowpair.ik(puma, TN[:1], q0=Q1[None])))
    # q0 (n,) seeds every row: the same as the row repeated
    same(ik_result(lowpair.ik(puma, TN, q0=Q1)), ik_result(lowpair.ik(puma, TN, q0=np.tile(Q1, (3, 1)))))


def _rotation(rvec):
    theta = np.linalg.norm(rvec)
    k = rvec / theta
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(theta) * K + (1 - math.cos(theta)) * K @ K


def test_simulate_frame_six_numbers_equal_the_4x4_to_rounding():
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = _rotation(FRAME6[:3]), FRAME6[3:]
    six = sim_result(lowpair.simulate(puma, q=QN, frame=FRAME6))
    four = sim_result(lowpair.simulate(puma, q=QN, frame=T))
    same(six, four, rtol=0.0, atol=1e-12)


# ----- fk's out= ---------------------------------------------------------------------------------------------

OUT_REFUSED = [
    ("float32", lambda shape: np.zeros(shape, dtype=np.float32), "C-contiguous float32"),
    ("fortran", lambda shape: np.zeros(shape, order="F"), "Fortran-ordered float64"),
    ("strided", lambda shape: np.zeros(shape[:-1] + (2 * shape[-1],))[..., ::2], "non-contiguous float64"),
    ("read-only", lambda shape: np.zeros(shape).view(), "read-only C-contiguous float64"),
    ("wrong shape", lambda shape: np.zeros((5, 4, 4)), "C-contiguous float64"),
]


@pytest.mark.parametrize("q", [Q1, QN], ids=["(n,)", "(N, n)"])
def test_fk_out_takes_a_c_contiguous_float64_of_the_result_shape(q):
    shape = (4, 4) if q.ndim == 1 else (len(q), 4, 4)
    buf = np.full(shape, 7.0)
    assert puma.fk(q, out=buf) is buf and np.array_equal(buf, puma.fk(q))
    for label, build, what in OUT_REFUSED:
        bad = build(shape)
        if label == "read-only":
            bad.setflags(write=False)
        given = "(5, 4, 4)" if label == "wrong shape" else "(" + ", ".join(map(str, shape)) + ")"
        with pytest.raises(lowpair.Error, match=rf"^out: expected a writeable C-contiguous float64 array of shape "
                                                rf"{re.escape('(' + ', '.join(map(str, shape)) + ')')}, got a "
                                                rf"{what} array of shape {re.escape(given)}"):
            puma.fk(q, out=bad)
    with pytest.raises(TypeError):  # not an array (docs/python.md "Errors")
        puma.fk(q, out=np.zeros(shape).tolist())


# ----- paths -------------------------------------------------------------------------------------------------


def _path_calls(tmp_path):
    csv = tmp_path / "m.csv"
    SIM.save(str(csv))
    return {
        "load": lambda p: lowpair.load(p).name,
        "read_measurements": lambda p: lowpair.read_measurements(p, puma).q.tolist(),
        "Robot.save": lambda p: puma.save(p),
        "Measurements.save": lambda p: SIM.save(p),
        "export": lambda p: lowpair.export(puma, p, format="urdf"),
    }, {"load": PUMA, "read_measurements": str(csv), "Robot.save": str(tmp_path / "r.yaml"),
        "Measurements.save": str(tmp_path / "s.csv"), "export": str(tmp_path / "r.urdf")}


PATH_FUNCTIONS = ["load", "read_measurements", "Robot.save", "Measurements.save", "export"]


@pytest.mark.parametrize("function", PATH_FUNCTIONS)
def test_a_path_is_a_str_or_an_os_pathlike(function, tmp_path):
    import pathlib
    calls, paths = _path_calls(tmp_path)
    by_str = calls[function](paths[function])
    text = open(paths[function]).read() if function != "load" and function != "read_measurements" else None
    assert calls[function](pathlib.Path(paths[function])) == by_str
    if text is not None:  # the same file (but its provenance comment, which names the path: equal here)
        assert open(paths[function]).read() == text
    with pytest.raises(lowpair.Error, match=r"^path: expected a str or os.PathLike, got int"):
        calls[function](3)
