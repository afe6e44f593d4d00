#include "io/robot_file_loads.hpp"

#include <cmath>
#include <stdexcept>

namespace lowpair::io {

JointLoadKeys readJointLoadKeys(const YamlReader& in, const YAML::Node& joint, const std::string& where,
                                double radians_per_unit) {
  const std::string& path = in.path();
  JointLoadKeys keys;
  if (joint["mass"]) {
    keys.mass = in.number(joint["mass"], where + ".mass");
    if (*keys.mass < 0.0) yamlError(path, joint["mass"], where + ".mass must be >= 0 (kg)");
  }
  if (joint["com"]) {
    const auto c = in.vector(joint["com"], 3, where + ".com");
    keys.com = Vec3(c[0], c[1], c[2]);
  }
  if (keys.mass.has_value() != keys.com.has_value()) {
    yamlError(path, joint, where + ": give 'mass' (kg) and 'com' (its link's centre of mass) together");
  }
  if (joint["compliance"]) keys.compliance = in.number(joint["compliance"], where + ".compliance") * radians_per_unit;
  if (joint["backlash"]) keys.backlash = in.number(joint["backlash"], where + ".backlash") * radians_per_unit;
  return keys;
}

void readLoads(const YamlReader& in, const YAML::Node& root, const std::vector<JointLoadKeys>& joints, RobotFile& file) {
  const std::string& path = in.path();
  const auto n = static_cast<Eigen::Index>(joints.size());
  bool link_masses = false, compliance = false, backlash = false;
  for (const JointLoadKeys& j : joints) {
    link_masses = link_masses || j.mass.has_value();
    compliance = compliance || j.compliance.has_value();
    backlash = backlash || j.backlash.has_value();
  }
  if (compliance) file.deflection.compliance = VecX::Zero(n);
  if (backlash) file.deflection.backlash = VecX::Zero(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const JointLoadKeys& j = joints[static_cast<size_t>(i)];
    if (j.compliance) file.deflection.compliance[i] = *j.compliance;
    if (j.backlash) file.deflection.backlash[i] = *j.backlash;
  }
  if (!link_masses && !root["payload"] && !root["gravity"]) return;
  MassModel masses;
  if (link_masses) {
    for (const JointLoadKeys& j : joints) masses.links.push_back(PointMass{j.mass.value_or(0.0), j.com.value_or(Vec3::Zero())});
  }
  if (const YAML::Node payload = root["payload"]) {
    in.allowOnly(payload, "payload", {"mass", "com"});
    if (!payload["mass"] || !payload["com"]) yamlError(path, payload, "payload needs 'mass' (kg) and 'com' (tool frame)");
    masses.payload.mass = in.number(payload["mass"], "payload.mass");
    if (masses.payload.mass < 0.0) yamlError(path, payload["mass"], "payload.mass must be >= 0 (kg)");
    const auto c = in.vector(payload["com"], 3, "payload.com");
    masses.payload.com = Vec3(c[0], c[1], c[2]);
  }
  if (const YAML::Node gravity = root["gravity"]) {
    const auto g = in.vector(gravity, 3, "gravity");
    masses.gravity = Vec3(g[0], g[1], g[2]);
  }
  const std::optional<double> metres = metresPerUnit(file.length_unit);
  if (!metres) {
    throw RobotFileError(path + ": masses need the length unit of their centres: length_unit " +
                         (file.length_unit.empty() ? std::string("is not given") : quotedFileText(file.length_unit) + " is not one lowpair converts") +
                         " (m, mm, cm, dm, um, km, in or ft)");
  }
  masses.metres_per_unit = *metres;
  file.masses = masses;
}

void writeJointLoadKeys(YAML::Emitter& out, const RobotFileExtras& extras, int joint, double radians_per_unit) {
  const auto i = static_cast<Eigen::Index>(joint);
  if (extras.masses && !extras.masses->links.empty()) {
    const PointMass& m = extras.masses->links[static_cast<size_t>(joint)];
    out << YAML::Key << "mass" << YAML::Value << m.mass;
    out << YAML::Key << "com" << YAML::Value << YAML::Flow << std::vector<double>{m.com[0], m.com[1], m.com[2]};
  }
  const JointDeflection& d = extras.deflection;
  if (d.compliance.size() > i && d.compliance[i] != 0.0) {
    out << YAML::Key << "compliance" << YAML::Value << d.compliance[i] / radians_per_unit;
  }
  if (d.backlash.size() > i && d.backlash[i] != 0.0) {
    out << YAML::Key << "backlash" << YAML::Value << d.backlash[i] / radians_per_unit;
  }
}

void checkLoadExtras(const RobotFileExtras& extras, int dof) {
  if (extras.masses) checkMassModel(*extras.masses, dof);
  for (const VecX* v : {&extras.deflection.compliance, &extras.deflection.backlash}) {
    if (v->size() != 0 && (v->size() != dof || !v->allFinite())) {
      throw std::invalid_argument("robot file: " + std::to_string(v->size()) + " deflection values for " +
                                  std::to_string(dof) + " joints, or one not finite");
    }
  }
}

void writeLoads(YAML::Emitter& out, const RobotFileExtras& extras) {
  if (!extras.masses) return;
  const MassModel& m = *extras.masses;
  const Vec3& c = m.payload.com;
  out << YAML::Key << "payload" << YAML::Value << YAML::Flow << YAML::BeginMap;
  out << YAML::Key << "mass" << YAML::Value << m.payload.mass;
  out << YAML::Key << "com" << YAML::Value << YAML::Flow << std::vector<double>{c[0], c[1], c[2]};
  out << YAML::EndMap;
  out << YAML::Key << "gravity" << YAML::Value << YAML::Flow << std::vector<double>{m.gravity[0], m.gravity[1], m.gravity[2]};
}

void scaleLoads(RobotFile& file, double f) {
  if (!file.masses) return;
  for (PointMass& m : file.masses->links) m.com *= f;
  file.masses->payload.com *= f;
  file.masses->metres_per_unit /= f;
}

}  // namespace lowpair::io
