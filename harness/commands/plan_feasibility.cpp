// What `lowpair plan` may draw and keep (plan_feasibility.hpp).
#include "commands/plan_feasibility.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>

#include "mujoco/collision_check.hpp"
#include "mujoco/messages.hpp"

namespace lowpair::commands {

namespace {

std::string number(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}

// A whole finite number, or nullopt.
std::optional<double> parseNumber(const std::string& text) {
  if (text.empty() || std::isspace(static_cast<unsigned char>(text.front()))) return std::nullopt;
  char* end = nullptr;
  errno = 0;
  const double x = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(x)) return std::nullopt;
  return x;
}

// joint `text` as a 0-based index: "1".."n", else a joint's name; -1 when none
int jointIndex(const PoeModel& model, const std::string& text) {
  const int n = model.dof();
  if (!text.empty() && std::all_of(text.begin(), text.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); })) {
    const long i = text.size() <= 9 ? std::stol(text) : 0;
    return i >= 1 && i <= n ? static_cast<int>(i - 1) : -1;
  }
  for (int i = 0; i < n; ++i) {
    if (model.joints()[static_cast<size_t>(i)].name == text) return i;
  }
  return -1;
}

std::string jointText(const PoeModel& model, int i) {
  const std::string& name = model.joints()[static_cast<size_t>(i)].name;
  return "joint " + std::to_string(i + 1) + (name.empty() ? "" : " (" + name + ")");
}

// the file's unit of joint i's range and its factor to q's unit
std::pair<std::string, double> rangeUnit(const io::RobotFile& file, const PoeModel& model, int i) {
  if (model.joint(i).type == JointType::Prismatic) return {file.length_unit.empty() ? "length" : file.length_unit, 1.0};
  return {file.angle_unit, file.angleFactor()};
}

// Adds the candidate's contacts to the counts.
void tally(const mujoco::ContactReport& c, const mujoco::CollisionChecker& checker, FeasibilityReport& r,
           std::map<std::pair<std::string, std::string>, int>& pairs) {
  (c.kind == mujoco::ContactKind::Self ? r.self_collision : c.kind == mujoco::ContactKind::World ? r.world : r.floor_contact)++;
  for (const auto& [b1, b2] : c.bodies) ++pairs[{checker.bodyName(b1), checker.bodyName(b2)}];
}

}  // namespace

RangeOverride parseRangeOverride(const std::string& text, const ArgumentSpelling& spelling) {
  const size_t second = text.rfind(':');
  const size_t first = second == std::string::npos || second == 0 ? std::string::npos : text.rfind(':', second - 1);
  if (first == std::string::npos || first == 0) {
    throw UsageError(spelling.name("range"), "expected J:LO:HI (J a joint index 1..n or a joint's name), got " +
                                                 io::quotedFileText(text));
  }
  RangeOverride r;
  r.joint = text.substr(0, first);
  const auto lo = parseNumber(text.substr(first + 1, second - first - 1));
  const auto hi = parseNumber(text.substr(second + 1));
  if (!lo || !hi) {
    throw UsageError(spelling.name("range"), io::quotedFileText(text) + ": LO and HI must be finite numbers");
  }
  if (!(*lo < *hi)) {
    throw UsageError(spelling.name("range"), io::quotedFileText(text) + ": LO must be below HI");
  }
  r.lo = *lo;
  r.hi = *hi;
  return r;
}

std::vector<Range> narrowedRanges(const io::RobotFile& file, const FeasibilityRequest& request,
                                  const ArgumentSpelling& spelling, std::vector<std::string>* source) {
  const PoeModel model = file.poeModel();
  std::vector<Range> ranges = samplingRanges(model);
  std::vector<std::string> from(ranges.size());
  for (int i = 0; i < model.dof(); ++i) from[static_cast<size_t>(i)] = model.joint(i).range ? "file" : "default";
  std::vector<bool> given(ranges.size(), false);
  for (const RangeOverride& o : request.ranges) {
    const int i = jointIndex(model, o.joint);
    if (i < 0) {
      throw UsageError(spelling.name("range"), "no joint " + io::quotedFileText(o.joint) + " in " + file.path + " (" +
                                                   std::to_string(model.dof()) + " joints: an index 1.." +
                                                   std::to_string(model.dof()) + " or a joint's name)");
    }
    const auto k = static_cast<size_t>(i);
    if (given[k]) throw UsageError(spelling.name("range"), jointText(model, i) + " is given twice");
    given[k] = true;
    if (!(o.lo < o.hi)) throw UsageError(spelling.name("range"), jointText(model, i) + ": LO must be below HI");
    const auto [unit, factor] = rangeUnit(file, model, i);
    const Range q{o.lo * factor, o.hi * factor};
    const double slack = 1e-12 * std::max({1.0, std::abs(ranges[k][0]), std::abs(ranges[k][1])});
    if (q[0] < ranges[k][0] - slack || q[1] > ranges[k][1] + slack) {
      throw UsageError(spelling.name("range"),
                       jointText(model, i) + ": [" + number(o.lo) + ", " + number(o.hi) + "] " + unit +
                           " is outside the " + (from[k] == "file" ? "file's" : "default") + " range [" +
                           number(ranges[k][0] / factor) + ", " + number(ranges[k][1] / factor) + "] " + unit);
    }
    ranges[k] = {std::max(q[0], ranges[k][0]), std::min(q[1], ranges[k][1])};
    from[k] = "--range";  // the CLI's name in both front ends: the JSON the Python tests compare
  }
  const double margin = request.range_margin;
  if (!std::isfinite(margin) || margin < 0) {
    throw UsageError(spelling.name("range_margin"), "must be a finite number >= 0, got " + number(margin));
  }
  for (int i = 0; i < model.dof() && margin > 0; ++i) {
    const auto k = static_cast<size_t>(i);
    const auto [unit, factor] = rangeUnit(file, model, i);
    const Range shrunk{ranges[k][0] + margin * factor, ranges[k][1] - margin * factor};
    if (!(shrunk[0] < shrunk[1])) {
      throw UsageError(spelling.name("range_margin"),
                       number(margin) + " " + unit + " at both ends leaves nothing of " + jointText(model, i) + "'s range [" +
                           number(ranges[k][0] / factor) + ", " + number(ranges[k][1] / factor) + "] " + unit);
    }
    ranges[k] = shrunk;
    from[k] += ", margin";
  }
  if (source) *source = from;
  return ranges;
}

std::vector<int> feasibleCandidates(const io::RobotFile& file, const std::vector<VecX>& candidates,
                                    const FeasibilityRequest& request, const ArgumentSpelling& spelling,
                                    FeasibilityReport& r) {
  r.drawn = static_cast<int>(candidates.size());
  if (request.floor && !std::isfinite(*request.floor)) {
    throw UsageError(spelling.name("floor"), "must be a finite number, got " + number(*request.floor));
  }
  std::vector<int> kept;
  if (request.model.empty()) {
    if (request.floor) throw UsageError(spelling.name("floor"), "needs a model to check (a robot given as MJCF/URDF, or " +
                                                                    spelling.name("model") + ")");
    for (int i = 0; i < r.drawn; ++i) kept.push_back(i);
    r.kept = r.drawn;
    return kept;
  }
  const auto start = std::chrono::steady_clock::now();
  // the chain's kinematics copy: its notes (what kinematics does not need) do not concern the collision check,
  // whose copy gives its own
  const bool same = request.model == file.path;
  const mujoco::NoteSink sink = mujoco::setNoteSink([](const std::string&) {});
  std::unique_ptr<mujoco::MujocoRobot> loaded;
  try {
    loaded = std::make_unique<mujoco::MujocoRobot>(request.model, request.tip, request.base);
  } catch (...) {
    mujoco::setNoteSink(sink);
    throw;
  }
  mujoco::setNoteSink(sink);
  const mujoco::MujocoRobot& robot = *loaded;
  const PoeModel model = mujoco::matchingModel(file, robot, request.model, request.tip);
  // a robot file beside the model: its lengths in metres, MuJoCo's unit (an extracted robot is the model's own)
  double metres = 1.0;
  if (!same) metres = io::metresPerUnit(file.length_unit).value_or(1.0);
  r.model = request.model;
  r.floor = request.floor;
  mujoco::CollisionChecker checker(robot, request.floor ? std::optional<double>(*request.floor * metres) : std::nullopt);
  // the robot given as the model gave its load's notes already; only the collision copy's own are new
  for (const std::string& n : checker.notes()) {
    if (!same || n.find("not checked") != std::string::npos) mujoco::emitNote(n);
  }
  r.collision_geoms = checker.collisionGeoms();
  if (r.collision_geoms == 0) {
    r.note = request.model + ": no geom can collide (none, or contype and conaffinity 0 on every one): nothing was "
                             "checked for collisions" + std::string(request.floor ? ", the floor included" : "");
    for (int i = 0; i < r.drawn; ++i) kept.push_back(i);
    r.kept = r.drawn;
    return kept;
  }
  r.checked = true;
  std::map<std::pair<std::string, std::string>, int> pairs;
  VecX x(model.dof());
  for (int c = 0; c < r.drawn; ++c) {
    const VecX& q = candidates[static_cast<size_t>(c)];
    for (int i = 0; i < model.dof(); ++i) {
      const JointMotion& motion = model.joint(i);
      x[i] = motion.motion(q[i]) * (motion.type == JointType::Prismatic ? metres : 1.0);
    }
    const mujoco::ContactReport contacts = checker.contactsAt(x);
    if (contacts.contacts == 0) {
      kept.push_back(c);
    } else {
      tally(contacts, checker, r, pairs);
    }
  }
  r.kept = static_cast<int>(kept.size());
  for (const auto& [bodies, n] : pairs) r.pairs.push_back({bodies.first, bodies.second, n});
  std::stable_sort(r.pairs.begin(), r.pairs.end(),
                   [](const BodyPairCount& a, const BodyPairCount& b) { return a.candidates > b.candidates; });
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return kept;
}

}  // namespace lowpair::commands
