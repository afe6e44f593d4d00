#include "io/output.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "lowpair/se3.hpp"
#include "lowpair/tolerances.hpp"

namespace lowpair::io {

using nlohmann::json;

namespace {
constexpr double kDeg = 180.0 / M_PI;

// beta only in a Hayati row (conventions.md, "Hayati rows"): a row without it is standard
json paramsJson(const DhParams& r) {
  json j = {{"theta", r.theta}, {"d", r.d}, {"alpha", r.alpha}, {"a", r.a}};
  if (r.hayati()) j["beta"] = r.beta;
  return j;
}

bool anyHayati(const DhModel& m) {
  return m.base().hayati() ||
         std::any_of(m.joints().begin(), m.joints().end(), [](const DhJoint& j) { return j.link.hayati(); });
}

std::string unitOr(const RobotFile& file) { return file.length_unit.empty() ? "length" : file.length_unit; }

json headerJson(const RobotFile& file, double size) {
  json j;
  j["name"] = file.name;
  j["source"] = file.path;
  j["length_unit"] = file.length_unit;
  j["size"] = size;
  return j;
}

json conditioningJson(const DhConversion& c) {
  json rows = json::array();
  for (const auto& r : c.rows) {
    rows.push_back({{"row", r.row}, {"axis_angle", r.axis_angle}, {"parallel", r.parallel},
                    {"ill_conditioned", r.ill_conditioned}});
  }
  return rows;
}

json fkCheckJson(const FkCheck& f) {
  return {{"samples", f.samples}, {"max_rotation", f.max_rotation}, {"max_translation", f.max_translation},
          {"scale", f.scale}};
}
}  // namespace

std::string robotLabel(const RobotFile& file) { return file.name.empty() ? file.path : file.name; }

std::vector<double> toVector(const Eigen::Ref<const VecX>& x) { return std::vector<double>(x.data(), x.data() + x.size()); }

std::string fixed(double x, int decimals) {
  char buf[64];
  if (x != 0.0 && (std::abs(x) >= 1e7 || std::abs(x) < 0.5 * std::pow(10.0, -decimals))) {
    std::snprintf(buf, sizeof buf, "%.*e", decimals, x);
  } else {
    std::snprintf(buf, sizeof buf, "%.*f", decimals, x);
  }
  std::string s = buf;
  bool all_zero = s.find_first_not_of("-0.") == std::string::npos;
  if (all_zero && s[0] == '-') s.erase(0, 1);
  return s;
}

std::string jsonText(const json& j) { return j.dump(1, ' ', false, json::error_handler_t::replace); }

void writeJsonWithRows(std::ostream& out, const json& head, const std::string& key, size_t count,
                       const std::function<json(size_t)>& row) {
  if (!head.is_object() || head.contains(key)) throw std::invalid_argument("writeJsonWithRows: head must be an object without " + key);
  // the document with an empty array at `key`; a dump holds no raw newline inside a string, so the key's line
  // (a newline, the one-space indent of the top level, the key) is found only where the key is
  json document = head;
  document[key] = json::array();
  const std::string text = jsonText(document);
  const std::string mark = "\n " + json(key).dump() + ": []";
  const size_t at = text.find(mark);
  if (at == std::string::npos) throw std::logic_error("writeJsonWithRows: the key's line was not found");
  const size_t array_at = at + mark.size() - 2;  // at the "[]"
  out.write(text.data(), static_cast<std::streamsize>(array_at));
  if (count == 0) {
    out << "[]";
  } else {
    // as nlohmann's serializer writes an array at depth 1 (indent 1): "[\n", each element at indent 2 (its
    // own dump with every line after the first indented by 2 more), ",\n" between, "\n ]"
    out << "[\n";
    std::string element;
    for (size_t k = 0; k < count; ++k) {
      element = "  ";
      for (const char c : jsonText(row(k))) {
        element += c;
        if (c == '\n') element += "  ";
      }
      element += k + 1 < count ? ",\n" : "\n ]";
      out.write(element.data(), static_cast<std::streamsize>(element.size()));
    }
  }
  out.write(text.data() + array_at + 2, static_cast<std::streamsize>(text.size() - array_at - 2));
}

json poseJson(const Pose& T) {
  json rows = json::array();
  const Mat4 M = T.matrix();
  for (int r = 0; r < 4; ++r) rows.push_back({M(r, 0), M(r, 1), M(r, 2), M(r, 3)});
  return rows;
}

std::vector<std::string> conversionWarnings(const DhConversion& c, const FkCheck& check) {
  std::vector<std::string> warnings;
  const double L = c.length_scale;
  auto message = [] {
    std::ostringstream msg;
    msg.precision(3);
    return msg;
  };
  for (const DhRowReport& r : c.rows) {
    if (!r.ill_conditioned) continue;
    std::ostringstream msg = message();
    const std::string what = r.row == 0 ? std::string("base row (joint 1's axis)")
                                        : "row of " + jointLabel(r.row - 1, c.model.joint(r.row - 1).name);
    msg << what << ": |d| = " << r.abs_d << ", |a| = " << r.abs_a << " exceed " << kIllConditioned << " L (L = " << L
        << "); the line before and after this row meet at " << r.axis_angle
        << " rad: nearly parallel axes make the D-H table ill-conditioned (Wu et al. §V)";
    warnings.push_back(msg.str());
  }
  if (c.tool.ill_conditioned) {
    std::ostringstream msg = message();
    msg << "tool: |d_T| = " << c.tool.abs_d << " exceeds " << kIllConditioned
        << " L: the last joint axis is nearly parallel to the tool z axis";
    warnings.push_back(msg.str());
  }
  if (c.above_rounding) {
    std::ostringstream msg = message();
    msg << "parallel threshold " << c.parallel_threshold << " is above rounding level ("
        << c.rounding_parallel_threshold << "): nearly parallel axes were snapped; FK deviation "
        << check.max_translation << " (length), " << check.max_rotation << " rad over " << check.samples
        << " configurations";
    warnings.push_back(msg.str());
  }
  return warnings;
}

std::vector<std::string> conversionNotes(const DhConversion& c) {
  std::vector<std::string> notes;
  for (const DhRowReport& r : c.rows) {
    if (r.parallel || !(r.axis_angle > 0.0 && r.axis_angle <= kNearlyParallelNote)) continue;
    const int n = c.model.dof();
    const std::string lines = r.row == 0 ? "the base z and joint 1's axis"
                              : r.row == n ? "joint " + std::to_string(n) + "'s axis and the tool z"
                                           : "the axes of joints " + std::to_string(r.row) + " and " + std::to_string(r.row + 1);
    // a threshold ten times the angle's sine, rounded up to a power of ten
    const double suggested = std::pow(10.0, std::ceil(std::log10(10.0 * std::sin(r.axis_angle))));
    std::ostringstream msg;
    msg.precision(2);
    msg << (r.row == 0 ? std::string("base row") : "row " + std::to_string(r.row)) << ": " << lines << " are parallel but for "
        << r.axis_angle << " rad (above the threshold " << c.parallel_threshold
        << "), so the row's theta and d are ill-conditioned; if they are parallel by design and a rounded angle in the file "
           "(1.5708 for pi/2) tilts them, --parallel-threshold "
        << suggested << " makes them parallel";
    notes.push_back(msg.str());
  }
  return notes;
}

json dhJson(const RobotFile& file, const DhConversion& c, const FkCheck& check) {
  json j = headerJson(file, c.length_scale);
  j["convention"] = "standard";
  j["base"] = paramsJson(c.model.base());
  j["joints"] = json::array();
  for (const DhJoint& dj : c.model.joints()) {
    json row = paramsJson(dj.link);
    row["type"] = jointTypeName(dj.type);
    if (!dj.name.empty()) row["name"] = dj.name;
    if (dj.type == JointType::Helical) row["pitch"] = dj.pitch;
    row["scale"] = dj.scale;
    j["joints"].push_back(row);
  }
  j["tool"] = {{"theta", c.model.toolTheta()}, {"d", c.model.toolD()}};
  j["parallel_threshold"] = c.parallel_threshold;
  j["conditioning"] = conditioningJson(c);
  j["fk_check"] = fkCheckJson(check);
  j["warnings"] = conversionWarnings(c, check);
  j["notes"] = conversionNotes(c);
  return j;
}

json modifiedDhJson(const RobotFile& file, const DhConversion& c, const FkCheck& check) {
  const ModifiedDh m = toModifiedDh(c.model);
  json j = headerJson(file, c.length_scale);
  j["convention"] = "modified";
  j["base"] = {{"theta", m.base_theta}, {"d", m.base_d}};
  j["joints"] = json::array();
  for (const ModifiedDhJoint& mj : m.joints) {
    json row = {{"type", jointTypeName(mj.type)}, {"alpha", mj.alpha}, {"a", mj.a}, {"theta", mj.theta}, {"d", mj.d}};
    if (mj.beta != 0.0) row["beta"] = mj.beta;  // the previous row is a Hayati row
    if (!mj.name.empty()) row["name"] = mj.name;
    if (mj.type == JointType::Helical) row["pitch"] = mj.pitch;
    row["scale"] = mj.scale;
    j["joints"].push_back(row);
  }
  j["tool"] = {{"alpha", m.tool_alpha}, {"a", m.tool_a}, {"theta", m.tool_theta}, {"d", m.tool_d}};
  j["conditioning"] = conditioningJson(c);
  j["fk_check"] = fkCheckJson(check);
  j["warnings"] = conversionWarnings(c, check);
  j["notes"] = conversionNotes(c);
  return j;
}

json poeJson(const RobotFile& file, const PoeModel& model) {
  json j = headerJson(file, model.lengthScale());
  j["joints"] = json::array();
  for (const Joint& jt : model.joints()) {
    json row = {{"type", jointTypeName(jt.type)}};
    if (!jt.name.empty()) row["name"] = jt.name;
    row["twist"] = {jt.twist[0], jt.twist[1], jt.twist[2], jt.twist[3], jt.twist[4], jt.twist[5]};
    if (jt.type == JointType::Helical) row["pitch"] = jt.pitch;
    row["scale"] = jt.scale;
    if (jt.offset != 0.0) row["offset"] = jt.offset;
    j["joints"].push_back(row);
  }
  j["tool_pose"] = poseJson(model.toolPose());
  const Vec6 xi = logSE3(model.toolPose());
  j["tool"] = {xi[0], xi[1], xi[2], xi[3], xi[4], xi[5]};
  return j;
}

int dhLengthDecimals(double L) {
  const double resolution = 1e-6 * (L > 0 && std::isfinite(L) ? L : 1.0);
  return std::clamp(static_cast<int>(std::ceil(-std::log10(resolution) - 1e-9)), 0, 12);
}

namespace {

void printWarnings(std::ostream& out, const DhConversion& c, const FkCheck& check) {
  out << "FK check: POE vs D-H over " << check.samples << " configurations: max rotation "
      << fixed(check.max_rotation, 2) << " rad, max translation " << fixed(check.max_translation, 2) << "\n";
  for (const auto& w : conversionWarnings(c, check)) out << "warning: " << w << "\n";
  for (const auto& note : conversionNotes(c)) out << "note: " << note << "\n";
}

std::string pitchUnit(const RobotFile& file) { return unitOr(file) + "/" + file.angle_unit; }
}  // namespace

void printDh(std::ostream& out, const RobotFile& file, const DhConversion& c, const FkCheck& check) {
  const std::string u = unitOr(file);
  out << robotLabel(file) << ": standard D-H (Wu et al. eq. 10), L = " << fixed(c.length_scale)
      << " " << u << "\n";
  out << "H = A(base) * prod_i [Q_i(scale_i q_i) * A(row i)] * Rz(theta_T) Tz(d_T),  A = Rz(theta) Tz(d) Rx(alpha) Tx(a)\n";
  const bool hayati = anyHayati(c.model);
  if (hayati) out << "a row with beta is a Hayati row: A = Rz(theta) Tx(a) Rx(alpha) Ry(beta), d = 0\n";
  out << "\n";
  const int ld = dhLengthDecimals(c.length_scale);
  const auto len = [ld](double x) { return fixed(x, ld); };
  const auto deg = [](double x) { return fixed(x * kDeg, kDhAngleDecimals); };
  char line[256];
  std::snprintf(line, sizeof line, "%-6s %-9s %-9s %14s %16s %14s %16s %14s %12s", "row", "frames", "joint",
                "theta(deg)", ("d(" + u + ")").c_str(), "alpha(deg)", ("a(" + u + ")").c_str(),
                ("pitch(" + pitchUnit(file) + ")").c_str(), "scale");
  out << line << (hayati ? "      beta(deg)" : "") << "\n";
  auto row = [&](const std::string& label, const std::string& frames, const std::string& type, const DhParams& r,
                 const std::string& pitch, const std::string& scale) {
    std::snprintf(line, sizeof line, "%-6s %-9s %-9s %14s %16s %14s %16s %14s %12s", label.c_str(), frames.c_str(),
                  type.c_str(), deg(r.theta).c_str(), len(r.d).c_str(), deg(r.alpha).c_str(), len(r.a).c_str(),
                  pitch.c_str(), scale.c_str());
    out << line;
    if (r.hayati()) {
      std::snprintf(line, sizeof line, " %14s", deg(r.beta).c_str());
      out << line;
    }
    out << "\n";
  };
  row("base", "B->0", "", c.model.base(), "", "");
  const int n = c.model.dof();
  for (int i = 0; i < n; ++i) {
    const DhJoint& dj = c.model.joint(i);
    const std::string pitch = dj.type == JointType::Helical ? fixed(dj.pitch * file.angleFactor(), 8) : "";
    char scale[32];
    std::snprintf(scale, sizeof scale, "%.9g", dj.scale);
    row(std::to_string(i + 1), std::to_string(i) + "->" + std::to_string(i + 1), jointTypeName(dj.type), dj.link, pitch,
        scale);
  }
  std::snprintf(line, sizeof line, "%-6s %-9s %-9s %14s %16s\n", "tool", (std::to_string(n) + "->T").c_str(), "",
                deg(c.model.toolTheta()).c_str(), len(c.model.toolD()).c_str());
  out << line << "\n";
  out << "Row i: joint i moves about (revolute) or along (prismatic) the z axis of frame i-1, then A(row i) leads to\n"
         "frame i; row n also carries the tool's first part (Wu et al. Fig. 3).\n";
  printWarnings(out, c, check);
}

void printModifiedDh(std::ostream& out, const RobotFile& file, const DhConversion& c, const FkCheck& check) {
  const ModifiedDh m = toModifiedDh(c.model);
  const std::string u = unitOr(file);
  out << robotLabel(file) << ": modified (Craig) D-H, L = " << fixed(c.length_scale) << " " << u
      << "\n";
  out << "H = Rz(theta_B) Tz(d_B) * prod_i [Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i + q) Tz(d_i)] * Rx(alpha_n) Tx(a_n) "
         "Rz(theta_T) Tz(d_T)\n";
  const bool hayati = anyHayati(c.model);
  if (hayati) out << "beta: of a Hayati row, Ry(beta) after Tx(a_{i-1})\n";
  out << "\n";
  const int ld = dhLengthDecimals(c.length_scale);
  const auto len = [ld](double x) { return fixed(x, ld); };
  const auto deg = [](double x) { return fixed(x * kDeg, kDhAngleDecimals); };
  char line[256];
  std::snprintf(line, sizeof line, "%-6s %-9s %14s %16s %14s %16s %14s %12s", "row", "joint", "alpha(deg)",
                ("a(" + u + ")").c_str(), "theta(deg)", ("d(" + u + ")").c_str(),
                ("pitch(" + pitchUnit(file) + ")").c_str(), "scale");
  out << line << (hayati ? "      beta(deg)" : "") << "\n";
  const auto beta = [&](double b) {
    char cell[32];
    std::snprintf(cell, sizeof cell, " %14s", deg(b).c_str());
    return hayati && b != 0.0 ? std::string(cell) : std::string();
  };
  std::snprintf(line, sizeof line, "%-6s %-9s %14s %16s %14s %16s\n", "base", "", "", "", deg(m.base_theta).c_str(),
                len(m.base_d).c_str());
  out << line;
  for (size_t i = 0; i < m.joints.size(); ++i) {
    const ModifiedDhJoint& j = m.joints[i];
    const std::string pitch = j.type == JointType::Helical ? fixed(j.pitch * file.angleFactor(), 8) : "";
    char scale[32];
    std::snprintf(scale, sizeof scale, "%.9g", j.scale);
    std::snprintf(line, sizeof line, "%-6zu %-9s %14s %16s %14s %16s %14s %12s", i + 1, jointTypeName(j.type),
                  deg(j.alpha).c_str(), len(j.a).c_str(), deg(j.theta).c_str(), len(j.d).c_str(),
                  pitch.c_str(), scale);
    out << line << beta(j.beta) << "\n";
  }
  std::snprintf(line, sizeof line, "%-6s %-9s %14s %16s %14s %16s", "tool", "", deg(m.tool_alpha).c_str(),
                len(m.tool_a).c_str(), deg(m.tool_theta).c_str(), len(m.tool_d).c_str());
  out << line;
  if (m.tool_beta != 0.0) out << std::string(28, ' ') << beta(m.tool_beta);
  out << "\n\n";
  printWarnings(out, c, check);
}

void printPoe(std::ostream& out, const RobotFile& file, const PoeModel& model) {
  const std::string u = unitOr(file);
  out << robotLabel(file) << ": base POE (Wu et al. eq. 5), unit twists [w; v] in the base "
      << "frame, L = " << fixed(model.lengthScale()) << " " << u << "\n\n";
  char line[256];
  std::snprintf(line, sizeof line, "%-5s %-9s %10s %10s %10s %12s %12s %12s %14s %12s\n", "joint", "type", "w_x", "w_y",
                "w_z", "v_x", "v_y", "v_z", ("pitch(" + pitchUnit(file) + ")").c_str(), "scale");
  out << line;
  for (int i = 0; i < model.dof(); ++i) {
    const Joint& j = model.joint(i);
    char scale[32];
    std::snprintf(scale, sizeof scale, "%.9g", j.scale);
    std::snprintf(line, sizeof line, "%-5d %-9s %10s %10s %10s %12s %12s %12s %14s %12s\n", i + 1, jointTypeName(j.type),
                  fixed(j.twist[0], 6).c_str(), fixed(j.twist[1], 6).c_str(), fixed(j.twist[2], 6).c_str(),
                  fixed(j.twist[3]).c_str(), fixed(j.twist[4]).c_str(), fixed(j.twist[5]).c_str(),
                  j.type == JointType::Helical ? fixed(j.pitch * file.angleFactor(), 8).c_str() : "", scale);
    out << line;
  }
  out << "\ntool pose exp(xi_T) = T_base_tool at the zero configuration:\n";
  printPose(out, model.toolPose(), u);
}

void printPose(std::ostream& out, const Pose& T, const std::string& length_unit) {
  const Mat4 M = T.matrix();
  for (int r = 0; r < 4; ++r) {
    char line[160];
    std::snprintf(line, sizeof line, "  [%12s %12s %12s | %14s]\n", fixed(M(r, 0), 9).c_str(), fixed(M(r, 1), 9).c_str(),
                  fixed(M(r, 2), 9).c_str(), fixed(M(r, 3), 6).c_str());
    out << (r == 3 ? "" : line);
  }
  out << "  position (" << length_unit << "): " << fixed(T.p.x(), 6) << " " << fixed(T.p.y(), 6) << " "
      << fixed(T.p.z(), 6) << "\n";
}

std::string shortest(double x) {
  char buffer[32];
  return std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, x).ptr);
}

}  // namespace lowpair::io
