#pragma once
/// @file simulation.hpp
/// The measurements of `lowpair simulate`, shared by the CLI and the Python module's lowpair.simulate: the
/// checks of the arguments and the measurement loop over a ground truth given as a function (the library's
/// FK of a robot file, or MuJoCo's tip pose), with the seeded noise and blunders of sampling.hpp.

#include <functional>
#include <string>
#include <vector>

#include "io/measurements.hpp"
#include "io/robot_file.hpp"
#include "commands/arguments.hpp"
#include "commands/sampling.hpp"

namespace lowpair::commands {

/// Upper bound on the random poses of a simulation (the CLI's --poses, Python's poses=).
constexpr int kMaxSimulatedPoses = 1000000;

/// Checks the target names a caller lists: each a target name (io::targetNameProblem), none twice, at most
/// io::kMaxTargets. @throws UsageError naming targets as `spelling` spells it
void checkTargetList(const std::vector<std::string>& names, const ArgumentSpelling& spelling);

/// The robot file's targets in order, for `identifiability` with targets (at least one): each with its point
/// (tool frame) and known flag, and numbered, not named (the parameters are `target.1.x`, ...).
/// @throws UsageError (subject: the file) naming the `targets:` list, the measure spelled as the front end does
std::vector<Target> numberedRobotFileTargets(const io::RobotFile& file, const ArgumentSpelling& spelling);

/// The targets measured of a robot file's `targets:` list: all, in the file's order, or those `names` lists
/// (checkTargetList), in the order listed; `points` gets each one's point in the tool frame.
/// @param robot_subject the robot file, named in messages
/// @throws UsageError: the file lists no targets (subject `robot_subject`), a bad or unknown name (targets)
std::vector<std::string> robotFileTargets(const std::vector<Target>& file_targets,
                                          const std::optional<std::vector<std::string>>& names,
                                          const std::string& robot_subject, const ArgumentSpelling& spelling,
                                          std::vector<Vec3>& points);

/// Checks the noise levels (each finite and in [0, limit]: 1e100 length, pi rad), that rotation noise goes
/// with pose measurements only, and that a target list (`targets_given`) goes with target measurements.
/// @throws UsageError naming the argument as `spelling` spells it
void checkSimulationArguments(Measure measure, double noise_position, double noise_rotation, bool targets_given,
                              const ArgumentSpelling& spelling);

/// Blunders: `count` measurements moved by `size` (length) in random directions.
struct Blunders {
  long long count = 0;
  double size = 0.0;
};

/// Checks a blunders argument: count a whole number in [0, io::kMaxMeasurements], size in (0, 1e100].
/// @throws UsageError naming blunders as `spelling` spells it
Blunders checkBlunders(double count, double size, const ArgumentSpelling& spelling);

/// The rows `poses` poses of a `joints`-joint robot measure, at most io::kMaxMeasurements, with at most
/// io::kMaxMeasurementJoints joints and io::kMaxMeasurementJointValues joint values in all (what a measurement file
/// holds: a file beyond them would not be read back, and 10^6 rows of 1000 joints would hold 8 GB).
/// @throws UsageError with subject `poses_subject` (the argument or file that sets the poses), or `robot_subject`
/// for the joints
long long simulationRows(long long poses, int joints, const MeasurementSetup& setup, const std::string& poses_subject,
                         const std::string& robot_subject);

/// Checks that the blunders are no more than the rows. @throws UsageError naming blunders
void checkBlunderCount(const Blunders& blunders, long long rows, const ArgumentSpelling& spelling);

/// The tool pose of the ground truth at joint variable q.
using TipPose = std::function<Pose(const VecX& q)>;

/// Where the poses come from: sample k of the stream `seed` within `ranges` (q_rows null), or row k of q_rows.
struct SimulationPoses {
  long long count = 0;
  std::vector<Range> ranges;        ///< per joint, in q
  const MatX* q_rows = nullptr;     ///< given joint vectors, one per row (count rows)
  /// Called (and must throw) when the tool at given row k has a coordinate above 1e100: the caller names the row.
  std::function<void(size_t k)> given_row_beyond_reach;
};

struct SimulatedMeasurements {
  std::vector<Measurement> measurements;
  std::vector<size_t> blunders;  ///< the rows moved, increasing
};

/// Measures every pose (appendMeasurements: the frame, then the noise of row r from (seed, r)), then moves
/// the blunders. Every number is one the measurement reader takes (|x| <= 1e100): sampled ranges within it,
/// then each tool position, then what the frame (`in_frame`), the noise and the blunders add.
/// @param robot_subject the robot's file, the subject of a range or a tool beyond 1e100
/// @throws UsageError naming the robot, frame, noise_position or blunders (as `spelling` spells them)
SimulatedMeasurements simulateMeasurements(const TipPose& tip_pose, const MeasurementSetup& setup,
                                           unsigned long long seed, const SimulationPoses& poses,
                                           const std::optional<Blunders>& blunders, bool in_frame,
                                           const std::string& robot_subject, const ArgumentSpelling& spelling);

}  // namespace lowpair::commands
