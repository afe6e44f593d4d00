// lowpair export ROBOT --format urdf|mjcf|poe|dh [--out FILE]   (export.hpp)
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>

#include "io/atomic_file.hpp"
#include "cli/commands.hpp"
#include "io/export.hpp"

namespace lowpair::cli {

using namespace lowpair::io;  // the rooms below

namespace {

struct ExportOptions {
  RobotSource robot;
  std::string format, out;
};

// How the file was made, for its header (no "--": XML comments cannot hold it).
std::string provenance(const ExportOptions& o) {
  std::string s = "Made by lowpair export from " + o.robot.path;
  if (!o.robot.tip.empty()) s += " (tip " + o.robot.tip + (o.robot.base.empty() ? "" : ", base " + o.robot.base) + ")";
  return s + ", format " + o.format + (o.out.empty() ? "" : ", written to " + o.out) + ".";
}

// The first joint whose variable is not its motion, for the usage error.
std::string firstMappedJoint(const PoeModel& model) {
  for (int i = 0; i < model.dof(); ++i) {
    const Joint& j = model.joint(i);
    if (j.scale != 1.0 || j.offset != 0.0) {
      char numbers[96];
      std::snprintf(numbers, sizeof numbers, "scale %.17g, offset %.17g", j.scale, j.offset);
      std::string label = jointLabel(i, j.name);  // one line on stderr, whatever the name holds
      std::replace_if(label.begin(), label.end(), [](char ch) { return ch == '\n' || ch == '\r'; }, ' ');
      return label + " has " + numbers;
    }
  }
  return "";
}

int runExport(const ExportOptions& o) {
  const ExportFormat format = parseExportFormat(o.format);
  const RobotFile file = loadRobot(o.robot, cliSpelling());
  const ExportedRobot exported = exportRobot(file, format, {provenance(o)});
  const char* what = format == ExportFormat::Urdf ? "URDF" : "MJCF";
  if (exported.joint_variables && o.out.empty()) {
    throw UsageError("--out", firstMappedJoint(file.poeModel()) + ": the " + what +
                                  "'s joint variable is the motion x = scale (q + offset), so export also writes the "
                                  "robot file of q next to the output; give --out FILE");
  }
  // notes after the files are written: a failed export prints its one error line and nothing else
  auto notes = [&] {
    for (const std::string& note : exported.notes) std::cerr << "note: " << note << "\n";
  };
  if (o.out.empty()) {
    notes();
    std::cout << exported.text;
    return 0;
  }
  if (!exported.joint_variables) {
    writeFileAtomically(o.out, exported.text);
    notes();
    std::cout << exportFormatName(format) << " written to " << o.out << "\n";
    return 0;
  }
  // both or neither: both are written to temporaries before either target is replaced, so a failed export
  // leaves an existing pair (or any file of those names) as it was
  const std::string variables = jointVariablesPath(o.out);
  StagedFiles files;
  files.stage(variables, *exported.joint_variables);
  files.stage(o.out, exported.text);
  files.commit();
  notes();
  std::cout << exportFormatName(format) << " written to " << o.out << "; its joint variable is x = scale (q + offset) of "
            << variables << "'s q (written too); ";
  if (exported.mujoco_readable) {
    std::cout << "validate with: lowpair validate " << o.out << " --tip tool --robot " << o.robot.path << "\n";
  } else {
    // beside the URDF, under a name that overwrites nothing (models/X.urdf often has a hand-written models/X.xml)
    const std::filesystem::path out(o.out);
    std::error_code ec;
    std::string xml = (out.parent_path() / (out.stem().string() + ".xml")).string();
    if (std::filesystem::exists(xml, ec) || ec) xml = (out.parent_path() / (out.stem().string() + ".export.xml")).string();
    std::cout << "MuJoCo cannot read its helical joints, validate the MJCF: lowpair export " << o.robot.path
              << " --format mjcf --out " << xml << ", then lowpair validate " << xml << " --tip tool --robot "
              << o.robot.path << "\n";
  }
  return 0;
}

}  // namespace

void addExportCommand(CLI::App& app, Commands& commands) {
  auto o = std::make_shared<ExportOptions>();
  auto* sub = app.add_subcommand("export", "the robot as a URDF, an MJCF, a POE or a D-H robot file");
  addRobotArgument(*sub, o->robot);
  sub->add_option("--format", o->format, "urdf, mjcf, poe or dh")
      ->required()
      ->check(CLI::IsMember({"urdf", "mjcf", "poe", "dh"}));
  sub->add_option("--out", o->out,
                  "write the file here (all or nothing) instead of standard output; URDF/MJCF of a robot whose joint "
                  "scales/offsets are not 1/0 also write <out stem>.joint_variables.yaml");
  commands.emplace_back(sub, [o] { return runExport(*o); });
}

}  // namespace lowpair::cli
