"""The third hostile audit (issue 30), its Python cases re-run as the audit ran them: each test here is one finding
and asserts the contract (lowpair.Error naming the argument, None for what is absent, the numbers the CLI gives).
The command-line cases are in tests/cli/third_audit_cli_test.cpp. Findings tested elsewhere:

| finding                                                              | test                                                           |
|----------------------------------------------------------------------|----------------------------------------------------------------|
| High: simulate(measure="targets", targets=[]): SIGSEGV reading .q    | test_array_safety.py::test_simulate_with_an_empty_target_list_is_refused |
| High: fk(Q, out=buf) with buf overlapping Q: 744 of 1000 rows wrong  | test_array_safety.py::test_fk_into_out_that_holds_q_equals_fk_of_a_copy |
| High: ik/compensate without a row limit: 10^7 rows SIGABRT           | test_array_safety.py::test_ik_and_compensate_refuse_rows_beyond_the_cli_limit |
| High: std::bad_alloc escaping as SIGABRT, not MemoryError            | test_out_of_memory.py::test_a_call_beyond_the_address_space_raises_memory_error |
| Unbounded: long calls ignore Ctrl-C (14.3 s after SIGINT)            | test_interrupt.py::test_python_ctrl_c_raises_keyboard_interrupt_within_a_second |
| Unbounded: ik seeds / compensate rows without a work bound           | test_work_limits.py::test_ik_seeds_beyond_the_work_limit_are_refused_naming_seeds, ...compensate... |
| Medium: fk, jacobian, ik, compensate of 1e300 non-finite; simulate q=1e200 | test_array_safety.py::test_joint_values_beyond_their_limits_are_refused_naming_the_index |
| Low: fk(Q, out=buf) with NaN in row 900 overwrote 768 rows           | test_array_safety.py::test_fk_refusal_leaves_out_as_it_was     |
| Low: complex and datetime64 arrays taken as joint values             | test_array_safety.py::test_arrays_that_are_not_real_numbers_are_refused_naming_argument_and_dtype |
| Low: a (1e9, 6) broadcast view refused with a TypeError              | test_array_safety.py::test_a_broadcast_view_beyond_the_row_limit_is_refused_before_any_copy |
| Low: a 10 MB argument quoted whole in the message                    | test_array_safety.py::test_a_huge_string_argument_is_cut_in_the_message |
| numpy: ik of one (4, 4) pose refused                                 | test_array_safety.py::test_ik_takes_one_4x4_pose_as_a_batch_of_one |
| numpy: float32 poses refused; rotations only as quaternions          | test_ik.py::test_ik_takes_float32_transforms_and_rotation_matrices |
| numpy: load(pathlib.Path) a TypeError dump                           | test_array_safety.py::test_load_takes_a_pathlike_and_names_other_types |
| numpy: MJCF notes on the C-level stderr, not warnings                | test_errors_threads.py::test_mjcf_loading_notes_are_python_warnings |
| numpy: no rotation measured: 0.0 in cal.before, None in to_dict()    | test_calibration.py::test_position_measurements                |
| numpy: out= of the wrong dtype/order: "(10, 4, 4), got (10, 4, 4)"   | test_array_safety.py::test_out_of_the_wrong_kind_names_what_differs |
| numpy: repr of select="cv" said "rank 33 of 39"                      | test_tracker.py::test_cross_validation_equals_cli              |
"""
import warnings

import numpy as np
import pytest

import lowpair

PUMA = "models/puma560_corke.yaml"
ACTUAL = "models/puma560_okamura_actual.yaml"
NOMINAL = "models/puma560_okamura_nominal.yaml"


def test_mjcf_length_unit_is_none_not_an_empty_string():
    # numpy user: robot.length_unit was '' for an MJCF ("absent quantities are None everywhere"); fixed here
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # (its loading notes: test_mjcf_loading_notes_are_python_warnings)
        robot = lowpair.load("models/puma560_corke.xml", tip="tool")
    assert robot.length_unit is None
    assert lowpair.load(PUMA).length_unit == "m"


def test_simulate_takes_a_4x4_frame():
    # numpy user: simulate(..., frame=np.eye(4)) raised a pybind11 TypeError dump
    robot = lowpair.load(PUMA)
    frame = np.eye(4)
    frame[:3, 3] = [0.5, -0.2, 0.1]
    moved = lowpair.simulate(robot, poses=4, seed=2, frame=frame)
    plain = lowpair.simulate(robot, poses=4, seed=2)
    # the measurement frame at T_base_frame: positions in it are T_base_frame^-1 p
    assert np.allclose(moved.positions, plain.positions - frame[:3, 3], atol=1e-12)
    with pytest.raises(lowpair.Error, match="frame"):
        lowpair.simulate(robot, poses=4, frame=np.eye(3))


def test_cross_validation_of_duplicate_poses_names_the_duplicates():
    # Low: calibrate(select="cv") of one pose repeated failed with "crossValidate: 1 poses for 5 folds"
    nominal = lowpair.load(NOMINAL)
    one = lowpair.simulate(lowpair.load(ACTUAL), poses=1, measure="position", seed=3)
    q, p = np.tile(one.q, (12, 1)), np.tile(one.positions, (12, 1))
    with pytest.raises(lowpair.Error, match=r"^folds: 5 folds but <arrays> holds 1 pose: .*duplicates") as error:
        lowpair.calibrate(nominal, q=q, positions=p, noise_position=0.01, select="cv")
    assert "crossValidate" not in str(error.value)
