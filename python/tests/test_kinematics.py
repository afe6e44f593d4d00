"""FK, Jacobians, D-H tables and singularities against the CLI (bit for bit) and finite differences."""
import numpy as np
import pytest

import lowpair
from conftest import ROBOT_FILES, cli_json, q_text

EPS = np.finfo(float).eps


def random_q(robot, count, seed):
    """Joint values inside each range (or a turn / +-L without one)."""
    rng = np.random.default_rng(seed)
    lo, hi = robot.ranges[:, 0].copy(), robot.ranges[:, 1].copy()
    for i, kind in enumerate(robot.joint_types):
        if np.isnan(lo[i]):
            width = np.pi if kind != "prismatic" else robot.length_scale
            lo[i], hi[i] = -width, width
    return lo + (hi - lo) * rng.random((count, robot.dof))


@pytest.mark.parametrize("path", ROBOT_FILES)
def test_fk_equals_cli_bit_for_bit(path):
    robot = lowpair.load(path)
    for q in random_q(robot, 3, seed=1):
        for model in ("poe", "dh"):
            expected = np.array(cli_json("fk", path, "--q", q_text(q), "--model", model)["T_base_tool"])
            T = robot.fk(q, model=model)
            assert T.shape == (4, 4) and T.dtype == np.float64
            assert np.array_equal(T, expected), (path, model, T - expected)
        assert np.array_equal(robot.fk(q), robot.fk(q, model=robot.model))


@pytest.mark.parametrize("path", ROBOT_FILES)
def test_batched_fk_equals_single_to_rounding(path):
    robot = lowpair.load(path)
    Q = random_q(robot, 1037, seed=2)  # not a multiple of the SIMD lanes or the chunk
    for model in ("poe", "dh"):
        Ts = robot.fk(Q, model=model)
        assert Ts.shape == (len(Q), 4, 4)
        single = np.stack([robot.fk(q, model=model) for q in Q])
        # docs/ik.md: batched agrees to rounding (measured 2 eps in R, 9 eps L in p); allow 4x that
        assert np.max(np.abs(Ts[:, :3, :3] - single[:, :3, :3])) <= 8 * EPS
        assert np.max(np.abs(Ts[:, :3, 3] - single[:, :3, 3])) <= 36 * EPS * robot.length_scale
        assert np.array_equal(Ts[:, 3, :], np.tile([0.0, 0.0, 0.0, 1.0], (len(Q), 1)))
    # Fortran order and integer input are accepted and give the same numbers
    assert np.array_equal(robot.fk(np.asfortranarray(Q)), robot.fk(Q))
    assert robot.fk(np.zeros((0, robot.dof))).shape == (0, 4, 4)


def test_fk_result_is_owned_by_numpy():
    robot = lowpair.load("models/puma560_corke.yaml")
    T = robot.fk(np.zeros(6))
    assert T.flags.owndata or T.base is not None
    T[0, 0] = 42.0  # writable, and a fresh array every call
    assert robot.fk(np.zeros(6))[0, 0] != 42.0


def numeric_jacobians(robot, q, h=1e-6):
    """Central differences of T(q): spatial [w; v], body [w; v], geometric [v; w]."""
    T = robot.fk(q, model="poe")
    Tinv = np.linalg.inv(T)
    n = robot.dof
    Js, Jb, Jg = np.zeros((6, n)), np.zeros((6, n)), np.zeros((6, n))
    vee = lambda W: np.array([W[2, 1], W[0, 2], W[1, 0]])  # noqa: E731
    for i in range(n):
        e = np.zeros(n)
        e[i] = h
        dT = (robot.fk(q + e, model="poe") - robot.fk(q - e, model="poe")) / (2 * h)
        S = dT @ Tinv
        B = Tinv @ dT
        Js[:, i] = np.r_[vee(S[:3, :3]), S[:3, 3]]
        Jb[:, i] = np.r_[vee(B[:3, :3]), B[:3, 3]]
        Jg[:, i] = np.r_[dT[:3, 3], vee(dT[:3, :3] @ T[:3, :3].T)]
    return {"spatial": Js, "body": Jb, "geometric": Jg}


@pytest.mark.parametrize("path", ROBOT_FILES)
def test_jacobians_against_central_differences(path):
    robot = lowpair.load(path)
    for q in random_q(robot, 3, seed=3):
        numeric = numeric_jacobians(robot, q)
        for frame, Jn in numeric.items():
            J = robot.jacobian(q, frame=frame)
            assert J.shape == (6, robot.dof)
            scale = max(1.0, robot.length_scale) * np.max(np.abs(robot.ranges[np.isfinite(robot.ranges)]), initial=1.0)
            assert np.max(np.abs(J - Jn)) <= 1e-7 * scale, (path, frame, np.max(np.abs(J - Jn)))


@pytest.mark.parametrize("frame", ["spatial", "body", "geometric"])
def test_jacobian_equals_cli(frame):
    path = "models/stanford_corke.yaml"
    robot = lowpair.load(path)
    q = random_q(robot, 1, seed=4)[0]
    expected = np.array(cli_json("jacobian", path, "--q", q_text(q), "--frame", frame)["jacobian"])
    assert np.array_equal(robot.jacobian(q, frame=frame), expected)


@pytest.mark.parametrize("path", ROBOT_FILES)
def test_dh_to_dict_equals_poe2dh_json(path):
    robot = lowpair.load(path)
    assert robot.dh().to_dict() == cli_json("poe2dh", path)
    assert robot.dh(modified=True).to_dict() == cli_json("poe2dh", path, "--modified")
    table = robot.dh()
    assert table.table.shape == (robot.dof, 4)
    assert len(table.rows) == robot.dof and table.base.keys() >= {"theta", "d", "alpha", "a"}


@pytest.mark.parametrize("path", ROBOT_FILES)
def test_singular_equals_cli(path):
    robot = lowpair.load(path)
    for q in [np.zeros(robot.dof), random_q(robot, 1, seed=5)[0]]:
        s = robot.singular(q)
        expected = cli_json("singular", path, "--q", q_text(q))
        assert s.to_dict() == expected
        assert s.rank == expected["rank"] and s.sigma_min == expected["sigma_min"]
        assert [c["class"] for c in s.classes] == [c["class"] for c in expected["classes"]]


def test_puma_wrist_singularity():
    s = lowpair.load("models/puma560_corke.yaml").singular(np.zeros(6))
    assert s.singular and s.rank == 5
    assert any(c["class"] == "C1" and c["joints"] == [4, 6] for c in s.classes)
    assert s.null_space.shape == (1, 6)


def test_robot_properties():
    robot = lowpair.load("models/puma560_corke.yaml")
    assert robot.name == "puma560-corke" and robot.dof == 6 and robot.length_unit == "m"
    assert robot.joint_types == ["revolute"] * 6 and len(robot.joint_names) == 6
    assert robot.ranges.shape == (6, 2) and robot.ranges.dtype == np.float64
    assert robot.model == "dh"


@pytest.mark.parametrize("model,tip", [("models/puma560_corke.xml", "tool"), ("models/puma560_corke.urdf", "tool")])
def test_model_files_with_tip(model, tip):
    robot = lowpair.load(model, tip=tip)
    q = np.array([0.1, -0.2, 0.3, 0.4, -0.5, 0.6])
    expected = np.array(cli_json("fk", model, "--tip", tip, "--q", q_text(q))["T_base_tool"])
    assert np.array_equal(robot.fk(q), expected)
    # the same robot as its robot file (MJCF/URDF in the file's unit or m)
    reference = lowpair.load("models/puma560_corke.yaml").fk(q)
    assert np.allclose(robot.fk(q), reference, atol=1e-9)


def test_identifiability_equals_cli():
    path = "models/puma560_okamura_nominal.yaml"
    robot = lowpair.load(path)
    for measure, free_pitch in (("pose", False), ("position", True)):
        ident = lowpair.identifiability(robot, measure=measure, poses=50, seed=1, free_pitch=free_pitch)
        args = ["identifiability", path, "--measure", measure, "--poses", "50", "--seed", "1"]
        expected = cli_json(*args, *(["--free-pitch"] if free_pitch else []))
        assert ident.to_dict() == expected
        assert ident.rank == expected["rank"] and ident.expected == expected["expected"]
        if measure == "pose":
            assert ident.rank == ident.expected  # pose measurements identify every parameter


def test_fk_out_buffer_and_help():
    robot = lowpair.load("models/puma560_corke.yaml")
    Q = random_q(robot, 50, seed=8)
    out = np.empty((50, 4, 4))
    assert robot.fk(Q, out=out) is out and np.array_equal(out, robot.fk(Q))
    single = np.empty((4, 4))
    assert robot.fk(Q[0], out=single) is single and np.array_equal(single, robot.fk(Q[0]))
    with pytest.raises(lowpair.Error, match="out: expected"):
        robot.fk(Q, out=np.empty((49, 4, 4)))
    with pytest.raises(lowpair.Error, match="out: expected"):
        robot.fk(Q, out=np.empty((50, 4, 4), dtype=np.float32))
    doc = lowpair.Robot.fk.__doc__
    assert "(N, 4, 4)" in doc and "rad" in doc and "length_unit" in doc
    for name in ("load", "calibrate", "identifiability", "export"):
        assert getattr(lowpair, name).__doc__


@pytest.mark.parametrize("count", [1037, 9001])  # 9001 poses = 1.15 MB: the non-temporal stores' path
def test_batched_fk_repacks_the_library_batch_bit_for_bit(count):
    import _lowpair_bench  # the C++ references beside the package (python/bench/timers.cpp)
    robot = lowpair.load("models/puma560_corke.yaml")
    Q = random_q(robot, count, seed=9)
    for model in ("poe", "dh"):
        reference = _lowpair_bench.batch_fk_reference(robot, Q, model=model)  # one forwardKinematicsBatch call
        T = robot.fk(Q, model=model)
        assert np.array_equal(T[:, :3, :3].reshape(count, 9), reference[:, :9])
        assert np.array_equal(T[:, :3, 3], reference[:, 9:])
        assert np.array_equal(T[:, 3, :], np.tile([0.0, 0.0, 0.0, 1.0], (count, 1)))
        out = np.full((count, 4, 4), np.nan)
        assert robot.fk(Q, model=model, out=out) is out and np.array_equal(out, T)


def test_fk_inputs_read_in_place_or_converted():
    robot = lowpair.load("models/puma560_corke.yaml")
    Q = random_q(robot, 40, seed=10)
    expected = robot.fk(Q)
    wide = np.zeros((40, 12))
    wide[:, ::2] = Q
    for same in (np.asfortranarray(Q), wide[:, ::2], Q.tolist(),
                 Q.astype(">f8")):
        assert np.array_equal(robot.fk(same), expected)
    assert np.array_equal(robot.fk(wide[0, ::2]), robot.fk(Q[0]))  # a strided (n,) view
    assert np.array_equal(robot.fk([0, 0, 0, 0, 0, 0]), robot.fk(np.zeros(6)))  # integers
    unaligned = np.frombuffer(b"\0" + np.ascontiguousarray(Q).tobytes(), dtype=np.float64, offset=1).reshape(40, 6)
    assert np.array_equal(robot.fk(unaligned), expected)
    # text is not numbers: an array of it is refused naming its dtype (numpy would parse '0.1'); a lone str is
    # not an array (TypeError)
    with pytest.raises(lowpair.Error, match=r"q: expected real numbers, got an array of dtype <U1"):
        robot.fk(["a"] * 6)
    with pytest.raises(TypeError, match="q: expected an array of numbers"):
        robot.fk("a")


def _documented(doc, name):
    """A docstring with text beyond pybind11's signature line `name(...) -> ...`."""
    if not doc or not doc.strip():
        return False
    lines = doc.strip().split("\n", 1)
    return not lines[0].startswith(name + "(") or (len(lines) > 1 and lines[1].strip() != "")


def test_every_public_function_and_property_is_documented():
    for name in lowpair.__all__:
        obj = getattr(lowpair, name)
        assert obj.__doc__, name
        if not isinstance(obj, type) or issubclass(obj, Exception):
            assert _documented(obj.__doc__, name), name
            continue
        for attr, value in vars(obj).items():
            if attr.startswith("_"):
                continue
            doc = value.__doc__ if isinstance(value, property) else getattr(value, "__doc__", None)
            assert _documented(doc, attr), f"{name}.{attr}"


def test_type_hints_cover_the_module():
    """__init__.pyi names every public class, property, method and function with the runtime's parameter names."""
    import ast
    import os
    import re
    hints = ast.parse(open(os.path.join(os.path.dirname(lowpair.__file__), "__init__.pyi")).read())
    functions = {n.name: n for n in hints.body if isinstance(n, ast.FunctionDef)}
    classes = {n.name: {m.name: m for m in n.body if isinstance(m, ast.FunctionDef)} for n in hints.body
               if isinstance(n, ast.ClassDef)}

    def runtime_parameters(doc):
        signature = doc.strip().split("\n", 1)[0]
        inside = signature[signature.index("(") + 1:signature.rindex(") ->")]
        return [p for p in re.findall(r"(?:^|, )(\w+):", inside) if p != "self"]

    def hinted_parameters(node):
        return [a.arg for a in node.args.args + node.args.kwonlyargs if a.arg != "self"]

    for name in lowpair.__all__:
        obj = getattr(lowpair, name)
        if isinstance(obj, type):
            assert name in classes, name
            if issubclass(obj, Exception):
                continue
            for attr, value in vars(obj).items():
                if attr.startswith("_") and attr != "__len__":
                    continue
                assert attr in classes[name], f"{name}.{attr} missing from __init__.pyi"
                if not isinstance(value, property):
                    assert hinted_parameters(classes[name][attr]) == runtime_parameters(value.__doc__), f"{name}.{attr}"
        else:
            assert name in functions, name
            assert hinted_parameters(functions[name]) == runtime_parameters(obj.__doc__), name
