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

#include "lowpair/kinematics.hpp"
#include "mujoco/collision_check.hpp"
#include "mujoco/line_of_sight.hpp"
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

namespace {

// The line of sight of the candidates free of contacts (FeasibilityRequest::tracker): the tracker, the targets
// (metres) and their normals, and the counts.
class SightJudge {
 public:
  SightJudge(const mujoco::CollisionChecker& checker, const io::RobotFile& file, const PoeModel& model,
             const FeasibilityRequest& request, double metres, FeasibilityReport& r)
      : sight_(checker), model_(model), data_(model), metres_(metres), r_(r) {
    tracker_base_ = *request.tracker * metres;
    for (size_t t = 0; t < file.targets.size(); ++t) {
      points_tool_.push_back(*file.targets[t].point_tool * metres);
      normals_tool_.push_back(t < file.target_normals.size() ? file.target_normals[t] : std::nullopt);
    }
    max_angle_ = request.smr_angle_deg * M_PI / 180.0;
    partial_ = request.partial;
  }

  // The tracker at the reference configuration: inside the world's geometry is a usage error.
  void checkTracker(mujoco::CollisionChecker& checker, const std::string& model_path, const ArgumentSpelling& spelling) {
    checker.contactsAt(VecX::Zero(model_.dof()));
    const Pose T = sight_.T_world_base();
    const int g = sight_.worldGeomHolding(T.p + T.R * tracker_base_);
    if (g >= 0) {
      throw UsageError(spelling.name("tracker"), "the tracker is inside " + sight_.geomText(g) + " of " + model_path +
                                                     ": no ray leaves it (give a point in free space, base frame)");
    }
  }

  // Which targets candidate q sees (the checker at q); false when it is rejected (counted).
  bool judge(const VecX& q, std::vector<bool>& seen) {
    forwardKinematics(model_, data_, q);
    const Pose& T_base_tool = data_.T_base_tool;
    const Pose T_world_base = sight_.T_world_base();
    const Vec3 tracker_world = T_world_base.p + T_world_base.R * tracker_base_;
    seen.assign(points_tool_.size(), false);
    bool any_seen = false, any_occluded = false;
    occluders_.clear();
    for (size_t t = 0; t < points_tool_.size(); ++t) {
      const Vec3 p_base = T_base_tool.R * points_tool_[t] + T_base_tool.p * metres_;
      const int g = sight_.blocker(tracker_world, T_world_base.p + T_world_base.R * p_base, kSmrRadiusMetres);
      if (g >= 0) {
        any_occluded = true;
        const std::pair<std::string, std::string> o{sight_.geomText(g), sight_.geomBody(g)};
        if (std::find(occluders_.begin(), occluders_.end(), o) == occluders_.end()) occluders_.push_back(o);
        continue;
      }
      if (normals_tool_[t]) {
        const Vec3 n_base = T_base_tool.R * *normals_tool_[t];
        const Vec3 to_tracker = tracker_base_ - p_base;
        if (std::atan2(n_base.cross(to_tracker).norm(), n_base.dot(to_tracker)) > max_angle_) continue;
      }
      seen[t] = true;
      any_seen = true;
    }
    for (const auto& o : occluders_) ++occluder_counts_[o];
    const bool all = std::find(seen.begin(), seen.end(), false) == seen.end();
    if (all || (partial_ && any_seen)) {
      if (!all) ++r_.partial_kept;
      return true;
    }
    ++(any_occluded ? r_.occluded : r_.angle);
    return false;
  }

  void finish() {
    for (const auto& [o, n] : occluder_counts_) r_.occluders.push_back({o.first, o.second, n});
    std::stable_sort(r_.occluders.begin(), r_.occluders.end(),
                     [](const OccluderCount& a, const OccluderCount& b) { return a.candidates > b.candidates; });
  }

 private:
  mujoco::LineOfSight sight_;
  const PoeModel& model_;
  Data data_;
  double metres_;
  FeasibilityReport& r_;
  Vec3 tracker_base_;
  std::vector<Vec3> points_tool_;
  std::vector<std::optional<Vec3>> normals_tool_;
  double max_angle_ = 0.0;
  bool partial_ = false;
  std::vector<std::pair<std::string, std::string>> occluders_;  // of the candidate being judged
  std::map<std::pair<std::string, std::string>, int> occluder_counts_;
};

// The request's own checks before any model is loaded.
void checkRequest(const io::RobotFile& file, const FeasibilityRequest& request, const ArgumentSpelling& spelling) {
  if (request.floor && !std::isfinite(*request.floor)) {
    throw UsageError(spelling.name("floor"), "must be a finite number, got " + number(*request.floor));
  }
  const std::string needs_model = "needs a model to check (a robot given as MJCF/URDF, or " + spelling.name("model") + ")";
  if (request.model.empty() && request.floor) throw UsageError(spelling.name("floor"), needs_model);
  if (!request.tracker) return;
  if (!request.tracker->allFinite()) throw UsageError(spelling.name("tracker"), "X, Y and Z must be finite numbers");
  if (request.model.empty()) throw UsageError(spelling.name("tracker"), needs_model);
  if (file.targets.empty()) {
    throw UsageError(spelling.name("tracker"), "needs target measurements (" + spelling.setting("measure", "targets") +
                                                   " and the robot file's targets: the SMRs it sees)");
  }
  // 180 degrees: no angle check; above it the cone means nothing more
  if (!(request.smr_angle_deg > 0.0 && request.smr_angle_deg <= 180.0)) {
    throw UsageError(spelling.name("smr_angle"), "must be in (0, 180] degrees, got " + number(request.smr_angle_deg));
  }
}

}  // namespace

std::vector<int> feasibleCandidates(const io::RobotFile& file, const std::vector<VecX>& candidates,
                                    const FeasibilityRequest& request, const ArgumentSpelling& spelling,
                                    FeasibilityReport& r) {
  r.drawn = static_cast<int>(candidates.size());
  checkRequest(file, request, spelling);
  std::vector<int> kept;
  if (request.model.empty()) {
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
  r.tracker = request.tracker;
  r.smr_angle_deg = request.smr_angle_deg;
  r.partial = request.partial;
  mujoco::CollisionChecker checker(robot, request.floor ? std::optional<double>(*request.floor * metres) : std::nullopt);
  // the robot given as the model gave its load's notes already; only the collision copy's own are new
  for (const std::string& n : checker.notes()) {
    if (!same || n.find("not checked") != std::string::npos) mujoco::emitNote(n);
  }
  r.collision_geoms = checker.collisionGeoms();
  std::optional<SightJudge> sight;
  if (request.tracker) {
    sight.emplace(checker, file, model, request, metres, r);
    sight->checkTracker(checker, request.model, spelling);
  }
  if (r.collision_geoms == 0) {
    r.note = request.model + ": no geom can collide (none, or contype and conaffinity 0 on every one): nothing was "
                             "checked for collisions" + std::string(request.floor ? ", the floor included" : "");
  }
  r.checked = r.collision_geoms > 0;
  if (!r.checked && !sight) {
    for (int i = 0; i < r.drawn; ++i) kept.push_back(i);
    r.kept = r.drawn;
    return kept;
  }
  std::map<std::pair<std::string, std::string>, int> pairs;
  VecX x(model.dof());
  std::vector<bool> seen;
  for (int c = 0; c < r.drawn; ++c) {
    const VecX& q = candidates[static_cast<size_t>(c)];
    for (int i = 0; i < model.dof(); ++i) {
      const JointMotion& motion = model.joint(i);
      x[i] = motion.motion(q[i]) * (motion.type == JointType::Prismatic ? metres : 1.0);
    }
    const mujoco::ContactReport contacts = checker.contactsAt(x);
    if (r.checked && contacts.contacts != 0) {
      tally(contacts, checker, r, pairs);
      continue;
    }
    if (sight && !sight->judge(q, seen)) continue;
    kept.push_back(c);
    if (sight) r.measured.push_back(seen);
  }
  if (sight) sight->finish();
  r.kept = static_cast<int>(kept.size());
  for (const auto& [bodies, n] : pairs) r.pairs.push_back({bodies.first, bodies.second, n});
  std::stable_sort(r.pairs.begin(), r.pairs.end(),
                   [](const BodyPairCount& a, const BodyPairCount& b) { return a.candidates > b.candidates; });
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return kept;
}

}  // namespace lowpair::commands
