// Fuzz target: the measurement CSV reader (harness/measurements.hpp), columns by name with six joint names
// (csv_columns.hpp). Allowed: RobotFileError. An accepted
// file's numbers are finite, its rotations orthonormal, its shape as documented; formatMeasurements of it
// reads back to the same joint values and positions.
#include "fuzz_common.hpp"
#include "io/measurements.hpp"
#include "io/robot_file.hpp"

// the harness rooms this test reads through
using namespace lowpair::io;

// Joint names a header may use instead of q1..qn (seeds/measurements/named_joints.csv).
const std::vector<std::string> kJointNames{"base", "shoulder", "elbow", "wrist1", "wrist2", "wrist3"};

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const lowpair_fuzz::TempFile file(".csv");
  static const lowpair_fuzz::TempFile again(".csv");
  lowpair::io::MeasurementFile m;
  try {
    m = lowpair::io::readMeasurements(file.write(data, size), {}, kJointNames);
  } catch (const lowpair::io::RobotFileError&) {
    return 0;
  }
  FUZZ_CHECK(m.dof >= 1 && m.dof <= lowpair::io::kMaxMeasurementJoints);
  FUZZ_CHECK(!m.measurements.empty() && m.measurements.size() <= size_t{lowpair::io::kMaxMeasurements});
  for (const lowpair::Measurement& x : m.measurements) {
    FUZZ_CHECK(x.q.size() == m.dof && x.q.allFinite());
    FUZZ_CHECK(lowpair_fuzz::finite(x.T_base_tool));
    FUZZ_CHECK((x.T_base_tool.R.transpose() * x.T_base_tool.R - lowpair::Mat3::Identity()).norm() < 1e-9);
  }
  // the writer's text reads back: joint values and positions bit for bit
  const std::string text = lowpair::io::formatMeasurements(m.measure, m.measurements, {"fuzz"}, m.target_names);
  lowpair::io::MeasurementFile back;
  try {
    back = lowpair::io::readMeasurements(again.write(reinterpret_cast<const uint8_t*>(text.data()), text.size()));
  } catch (const lowpair::io::RobotFileError& e) {
    std::fprintf(stderr, "formatMeasurements output rejected: %s\n", e.what());
    std::abort();
  }
  FUZZ_CHECK(back.measure == m.measure && back.dof == m.dof && back.measurements.size() == m.measurements.size());
  FUZZ_CHECK(back.target_names == m.target_names);
  for (size_t i = 0; i < m.measurements.size(); ++i) {
    FUZZ_CHECK(back.measurements[i].target == m.measurements[i].target);
    FUZZ_CHECK(back.measurements[i].q == m.measurements[i].q);
    FUZZ_CHECK(back.measurements[i].T_base_tool.p == m.measurements[i].T_base_tool.p);
  }
  return 0;
}
