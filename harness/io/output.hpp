#pragma once
/// @file output.hpp
/// JSON and human-readable renderings of models, conversions and poses (the CLI's contract, README).

#include <cmath>
#include <functional>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "lowpair/convert.hpp"
#include "io/robot_file.hpp"

namespace lowpair::io {

/// `j` as indented JSON text (one space). Strings that are not valid UTF-8 (a name read from a file) are
/// written with U+FFFD in place of the invalid bytes instead of failing the command.
std::string jsonText(const nlohmann::json& j);
/// Writes jsonText(document) to `out`, byte for byte, where document is `head` (an object without `key`) with
/// `key` set to the array [row(0), ..., row(count - 1)]: one row's JSON value is made at a time (10^6 rows of
/// `fk --q-file --json` held as one document took 3.7 GB).
void writeJsonWithRows(std::ostream& out, const nlohmann::json& head, const std::string& key, size_t count,
                       const std::function<nlohmann::json(size_t)>& row);
/// A number as JSON, null where it is not finite (JSON has no inf or NaN: an undetermined deviation, no redundancy).
inline nlohmann::json finiteOrNull(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

nlohmann::json poseJson(const Pose& T);
/// The table with its conditioning, the FK check `check` of it and the warnings (conversionWarnings).
nlohmann::json dhJson(const RobotFile& file, const DhConversion& conversion, const FkCheck& check);
nlohmann::json modifiedDhJson(const RobotFile& file, const DhConversion& conversion, const FkCheck& check);
nlohmann::json poeJson(const RobotFile& file, const PoeModel& model);

void printDh(std::ostream& out, const RobotFile& file, const DhConversion& conversion, const FkCheck& check);
void printModifiedDh(std::ostream& out, const RobotFile& file, const DhConversion& conversion, const FkCheck& check);
void printPoe(std::ostream& out, const RobotFile& file, const PoeModel& model);
void printPose(std::ostream& out, const Pose& T, const std::string& length_unit);

/// The conversion's conditioning in sentences (conversion.md, "Accuracy and conditioning"): one per
/// ill-conditioned row, one for an ill-conditioned tool, one for a parallel threshold above rounding level
/// (with the deviation `check` measured).
std::vector<std::string> conversionWarnings(const DhConversion& conversion, const FkCheck& check);
/// Rows whose lines meet at a positive angle up to this (rad) get a note (conversionNotes): such a pair is
/// parallel by design far more often than not, tilted by an angle a file rounds (1.5708 for pi/2 is 3.7e-6
/// rad off), and the row's theta and d are then ill-conditioned. Tilts a calibration finds are larger (1e-4
/// rad and up).
constexpr double kNearlyParallelNote = 1e-5;
/// One sentence per such row, pointing at `--parallel-threshold` with a value that makes the pair parallel.
std::vector<std::string> conversionNotes(const DhConversion& conversion);

/// The robot's name, or its file when it has none.
std::string robotLabel(const RobotFile& file);
/// A vector as a JSON-ready std::vector.
std::vector<double> toVector(const Eigen::Ref<const VecX>& x);

/// The shortest text that reads back as x ("0.01", "1e+100", "nan"; at most 17 significant digits):
/// numbers quoted in messages.
std::string shortest(double x);

/// "12.3456" for moderate magnitudes, "1.2346e+07" beyond; never "-0.0000".
std::string fixed(double x, int decimals = 4);

/// Decimals of a D-H table's lengths, about 1e-6 L (the table shows what a controller's D-H entries need;
/// the numbers are known to rounding, far better), and of its angles in degrees, 1e-6 deg.
int dhLengthDecimals(double L);
constexpr int kDhAngleDecimals = 6;

}  // namespace lowpair::io
