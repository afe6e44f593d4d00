// A D-H table with standard deviations, as text and JSON (calibration_output.hpp printDhWithDeviations,
// dhUncertaintyJson): calibrate's calibrated table and plan's expected one.
#include <array>
#include <cstdio>

#include "commands/calibration_output.hpp"
#include "commands/calibration_output_parts.hpp"
#include "io/output.hpp"

namespace lowpair::commands {

using namespace lowpair::io;  // the rooms below
using namespace detail;

using nlohmann::json;

void printDhWithDeviations(std::ostream& out, const io::RobotFile& file, const DhUncertainty& dh,
                           const std::string& deviations_title) {
  const DhModel& m = dh.conversion.model;
  const std::string u = lengthUnit(file);
  char line[256];
  const int ld = io::dhLengthDecimals(dh.conversion.length_scale);
  const std::string pu = pitchUnit(file);
  const double pitch_factor = file.angleFactor();
  // a Hayati row (conventions.md) has a beta column: printed only when some row is one
  bool hayati = m.base().hayati();
  for (const DhJoint& j : m.joints()) hayati = hayati || j.link.hayati();
  auto header = [&] {
    std::snprintf(line, sizeof line, "%-6s %-9s %14s %16s %14s %16s %14s %12s", "row", "joint", "theta(deg)",
                  ("d(" + u + ")").c_str(), "alpha(deg)", ("a(" + u + ")").c_str(), ("pitch(" + pu + ")").c_str(), "scale");
    out << line << (hayati ? "   beta(deg)" : "") << "\n";  // 120 columns with it
  };
  auto tableRow = [&](const std::string& label, const std::string& type, const std::array<std::string, 7>& e) {
    std::snprintf(line, sizeof line, "%-6s %-9s %14s %16s %14s %16s %14s %12s %11s\n", label.c_str(), type.c_str(),
                  e[0].c_str(), e[1].c_str(), e[2].c_str(), e[3].c_str(), e[4].c_str(), e[5].c_str(), e[6].c_str());
    std::string text = line;
    text.erase(text.find_last_not_of(" \n") + 1);  // no trailing blanks where a row has no pitch or scale
    out << text << "\n";
  };
  auto values = [&](const DhParams& v) -> std::array<std::string, 7> {
    return {fixed(v.theta * kDeg, io::kDhAngleDecimals), fixed(v.d, ld), fixed(v.alpha * kDeg, io::kDhAngleDecimals),
            fixed(v.a, ld), "", "", v.hayati() ? fixed(v.beta * kDeg, io::kDhAngleDecimals) : ""};
  };
  header();
  tableRow("base", "", values(m.base()));
  for (int i = 0; i < m.dof(); ++i) {
    const DhJoint& j = m.joint(i);
    auto e = values(j.link);
    if (j.type == JointType::Helical) e[4] = fixed(j.pitch * pitch_factor, 8);
    char scale[32];
    std::snprintf(scale, sizeof scale, "%.9g", j.scale);
    e[5] = scale;
    tableRow(std::to_string(i + 1), jointTypeName(j.type), e);
  }
  tableRow("tool", "", {fixed(m.toolTheta() * kDeg, io::kDhAngleDecimals), fixed(m.toolD(), ld), "", "", "", "", ""});

  // "fixed": set by the convention (a row placed by a prismatic axis has a = d = 0), not measured
  // "fixed (gauge)": set by the base-frame rule (calibrate in the nominal's base frame)
  auto sdOf = [](double sd, double factor, bool is_fixed, bool gauge) {
    return gauge ? std::string("fixed (gauge)") : is_fixed ? std::string("fixed") : deviation(sd * factor);
  };
  auto deviations = [&](const DhParams& sd, const DhUncertainty::Fixed& f) -> std::array<std::string, 7> {
    return {sdOf(sd.theta, kDeg, false, f.gauge_theta), sdOf(sd.d, 1.0, f.d, f.gauge_d),
            sdOf(sd.alpha, kDeg, false, f.gauge_alpha), sdOf(sd.a, 1.0, f.a, f.gauge_a), "", "",
            sd.hayati() ? deviation(sd.beta * kDeg) : ""};
  };
  auto gauged = [](const DhUncertainty::Fixed& f) { return f.gauge_theta || f.gauge_d || f.gauge_alpha || f.gauge_a; };
  const bool any_gauge = gauged(dh.base_fixed) || (!dh.links_fixed.empty() && gauged(dh.links_fixed[0]));
  out << "\n" << deviations_title << " (same units; fixed: set by the D-H convention):\n";
  if (any_gauge) out << "fixed (gauge): set by the base frame (joint 1's line, its zero, the common normal's foot)\n";
  header();
  tableRow("base", "", deviations(dh.base, dh.base_fixed));
  for (int i = 0; i < m.dof(); ++i) {
    const auto k = static_cast<size_t>(i);
    auto e = deviations(dh.links[k], dh.links_fixed[k]);
    if (m.joint(i).type == JointType::Helical) e[4] = deviation(dh.pitch[k] * pitch_factor);
    e[5] = deviation(dh.scale[k]);
    tableRow(std::to_string(i + 1), jointTypeName(m.joint(i).type), e);
  }
  tableRow("tool", "", {deviation(dh.tool_theta * kDeg), deviation(dh.tool_d), "", "", "", "", ""});
}

json dhUncertaintyJson(const DhUncertainty& dh) {
  // (`fixed`: the entries the D-H convention sets, standard deviation 0)
  auto row = [](const DhParams& v, const DhParams& sd, const DhUncertainty::Fixed& f) {
    json fixed = json::array();
    if (f.d) fixed.push_back("d");
    if (f.a) fixed.push_back("a");
    json o{{"theta", v.theta}, {"d", v.d}, {"alpha", v.alpha}, {"a", v.a},
           {"sd", {{"theta", finiteOrNull(sd.theta)}, {"d", finiteOrNull(sd.d)}, {"alpha", finiteOrNull(sd.alpha)},
                   {"a", finiteOrNull(sd.a)}}},
           {"fixed", fixed}};
    if (v.hayati()) {  // beta only in a Hayati row (conventions.md)
      o["beta"] = v.beta;
      o["sd"]["beta"] = finiteOrNull(sd.beta);
    }
    // the entries the base frame (the gauge) sets: sd 0, "fixed_by": {"theta": "gauge", ...}
    json by = json::object();
    if (f.gauge_theta) by["theta"] = "gauge";
    if (f.gauge_d) by["d"] = "gauge";
    if (f.gauge_alpha) by["alpha"] = "gauge";
    if (f.gauge_a) by["a"] = "gauge";
    if (!by.empty()) o["fixed_by"] = by;
    return o;
  };
  const DhModel& m = dh.conversion.model;
  json joints = json::array();
  for (int i = 0; i < m.dof(); ++i) {
    const auto k = static_cast<size_t>(i);
    json j = row(m.joint(i).link, dh.links[k], dh.links_fixed[k]);
    j["type"] = jointTypeName(m.joint(i).type);
    if (m.joint(i).type == JointType::Helical) {  // (docs/file_formats.md: pitch on helical rows only)
      j["pitch"] = m.joint(i).pitch;
      j["sd"]["pitch"] = finiteOrNull(dh.pitch[k]);
    }
    j["scale"] = m.joint(i).scale;
    j["sd"]["scale"] = finiteOrNull(dh.scale[k]);
    joints.push_back(j);
  }
  return {{"base", row(m.base(), dh.base, dh.base_fixed)},
          {"joints", joints},
          {"tool", {{"theta", m.toolTheta()}, {"d", m.toolD()},
                    {"sd", {{"theta", finiteOrNull(dh.tool_theta)}, {"d", finiteOrNull(dh.tool_d)}}}}}};
}

}  // namespace lowpair::commands
