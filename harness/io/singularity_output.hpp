#pragma once
/// @file singularity_output.hpp
/// The words and the JSON of a singularity analysis (`lowpair singular`, the Python module's
/// Robot.singular): one sentence per singular class (conventions.md "Singularities") and the report.

#include <nlohmann/json.hpp>
#include <string>

#include "io/robot_file.hpp"
#include "lowpair/singularity.hpp"

namespace lowpair::io {

/// Null vectors printed (text and JSON) at most: a robot of up to 6 joints, or any rank loss of a 6-joint
/// arm, is printed in full; beyond that the basis is the self-motion of a redundant chain, n numbers per
/// vector, and the rest is counted, not printed (10,000 joints would print ~1 GB).
constexpr int kPrintedNullVectors = 6;

/// One line per class, from the class's joints and geometry: "joint axes 4 and 6 are collinear".
std::string singularClassText(const SingularClass& c);

/// `lowpair singular --json` (docs/file_formats.md): the report of `file`'s robot at `q`.
nlohmann::json singularityJson(const RobotFile& file, const VecX& q, const SingularityReport& r);

}  // namespace lowpair::io
