#pragma once
// The shipped models with masses (mujoco_dynamics_test.cpp, mujoco_gravity_test.cpp): the files in models/
// carry placeholder inertials (MJCF: 1 kg at each body's origin; URDF: 1 g) and MJCF gravity 0, so each test
// writes a variant with seeded random masses (0.5..20 kg) and centres of mass (each coordinate within
// 0.25 m of the body's frame), a tilted gravity in the MJCF (the URDF keeps MuJoCo's default 0 0 -9.81), and
// in the MJCF one more weighing body fixed beyond the tip site's body (lumped into the last link). The URDF of
// puma560_okamura_actual is left out: its helical joints use <mimic>, which MuJoCo 2.2.2 ignores.
#include <fstream>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "scratch_folder.hpp"

namespace mass_variants {

struct Variant {
  std::string name, path, tip, base;
};

inline const harness_test::Scratch& scratch() {
  static const harness_test::Scratch s("lowpair_mass_variants");
  return s;
}

inline std::string readText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline std::string number(double x) {
  std::ostringstream s;
  s.precision(17);
  s << x;
  return s.str();
}

// Replaces each match of `pattern` by make(), in order.
template <class Make>
std::string replaceEach(const std::string& text, const std::regex& pattern, Make make) {
  std::string out;
  auto end = std::sregex_iterator();
  size_t last = 0;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), pattern); it != end; ++it) {
    const size_t at = static_cast<size_t>(it->position());
    out += text.substr(last, at - last) + make();
    last = at + static_cast<size_t>(it->length());
  }
  return out + text.substr(last);
}

inline std::vector<Variant> variants(unsigned long long seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> mass(0.5, 20.0), offset(-0.25, 0.25);
  const std::string models = LOWPAIR_MODELS;
  const std::vector<std::string> names = {"elbow_mls",       "panda",      "puma560_corke", "puma560_okamura_actual",
                                          "puma560_okamura_nominal", "rhino_xr3_slide", "stanford_corke"};
  auto mjcfInertial = [&] {
    return "<inertial pos=\"" + number(offset(rng)) + " " + number(offset(rng)) + " " + number(offset(rng)) +
           "\" mass=\"" + number(mass(rng)) + "\" diaginertia=\"0.01 0.01 0.01\"/>";
  };
  auto urdfInertial = [&] {
    return "<inertial><origin xyz=\"" + number(offset(rng)) + " " + number(offset(rng)) + " " + number(offset(rng)) +
           "\" rpy=\"0 0 0\"/><mass value=\"" + number(mass(rng)) +
           "\"/><inertia ixx=\"0.01\" iyy=\"0.01\" izz=\"0.01\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial>";
  };
  std::vector<Variant> out;
  for (const std::string& n : names) {
    std::string xml = readText(models + "/" + n + ".xml");
    xml = replaceEach(xml, std::regex("<inertial [^>]*/>"), mjcfInertial);
    xml = std::regex_replace(xml, std::regex("<option gravity=\"0 0 0\"/>"), "<option gravity=\"1.5 -2 -9.6\"/>");
    xml = std::regex_replace(xml, std::regex("(<site name=\"tool\"[^>]*/>)"),
                             "$1<body name=\"beyond_tip\" pos=\"0.05 0.02 0.1\">" + mjcfInertial() + "</body>");
    out.push_back({n + ".xml", scratch().write(n + ".xml", xml), "tool", ""});
    if (n == "puma560_okamura_actual") continue;  // its URDF's helical joints use <mimic>, which MuJoCo 2.2.2 ignores
    std::string urdf = readText(models + "/" + n + ".urdf");
    urdf = replaceEach(urdf, std::regex("<inertial>[\\s\\S]*?</inertial>"), urdfInertial);
    out.push_back({n + ".urdf", scratch().write(n + ".urdf", urdf), "tool", ""});
  }
  return out;
}

}  // namespace mass_variants
