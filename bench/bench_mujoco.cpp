// MuJoCo peers: mj_kinematics (FK) and mj_kinematics + mj_comPos + mj_jacSite (Jacobian) on the robots'
// MJCF files, site "tool". qpos = qpos0 + x, x = scale (q + offset) of the robot file's POE joints (design.md
// "MuJoCo facts", harness/commands/sampling.hpp: the same map `lowpair validate` uses).
#include <benchmark/benchmark.h>
#include <mujoco/mujoco.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "registration.hpp"
#include "robots.hpp"

namespace lowpair_bench {

namespace {

struct MjModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct MjDataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};

struct MujocoFixture {
  explicit MujocoFixture(const RobotCase& robot) : r(robot) {
    char error[1000] = "";
    m.reset(mj_loadXML(r.mjcf.c_str(), nullptr, error, sizeof error));
    if (!m) throw std::runtime_error(r.mjcf + ": " + error);
    d.reset(mj_makeData(m.get()));
    site = mj_name2id(m.get(), mjOBJ_SITE, "tool");
    if (site < 0) throw std::runtime_error(r.mjcf + ": no site named tool");
    if (m->njnt != r.dof || m->nv != r.dof) {
      throw std::runtime_error(r.mjcf + ": " + std::to_string(m->njnt) + " joints, the robot file " + std::to_string(r.dof) +
                               " (the MuJoCo benchmarks take one hinge or slide per joint, no coupled pairs)");
    }
    jacp.resize(static_cast<size_t>(3 * m->nv));
    jacr.resize(static_cast<size_t>(3 * m->nv));
    std::vector<double> J(static_cast<size_t>(6 * r.dof));
    for (int k = 0; k < kPool; ++k) {
      load(k);
      mj_kinematics(m.get(), d.get());
      double pose[12];
      for (int e = 0; e < 9; ++e) pose[e] = d->site_xmat[9 * site + e];
      for (int e = 0; e < 3; ++e) pose[9 + e] = d->site_xpos[3 * site + e];
      fk_error = std::max(fk_error, poseMismatch(r, k, pose));
      mj_comPos(m.get(), d.get());
      mj_jacSite(m.get(), d.get(), jacp.data(), jacr.data(), site);
      std::copy(jacp.begin(), jacp.end(), J.begin());
      std::copy(jacr.begin(), jacr.end(), J.begin() + 3 * r.dof);
      for (int e = 0; e < 6 * r.dof; ++e) {  // d/dx -> d/dq
        J[static_cast<size_t>(e)] *= r.scale_mujoco[static_cast<size_t>(e % r.dof)];
      }
      jac_error = std::max(jac_error, jacobianMismatch(r, k, J.data()));
    }
  }
  void load(int k) {
    const double* x = &r.x_mujoco[static_cast<size_t>(k * r.dof)];
    for (int i = 0; i < r.dof; ++i) {
      const int adr = m->jnt_qposadr[i];
      d->qpos[adr] = m->qpos0[adr] + x[i];
    }
  }
  const RobotCase& r;
  std::unique_ptr<mjModel, MjModelDeleter> m;
  std::unique_ptr<mjData, MjDataDeleter> d;
  int site = -1;
  std::vector<double> jacp, jacr;
  double fk_error = 0.0, jac_error = 0.0;
};

MujocoFixture& fixture(RobotId id) {
  static std::unique_ptr<MujocoFixture> cache[kRobotIds];
  auto& slot = cache[static_cast<int>(id)];
  if (!slot) slot.reset(new MujocoFixture(robotCase(id)));
  return *slot;
}

bool rejected(benchmark::State& state, double error, const char* what) {
  if (error <= kAgree) return false;
  state.SkipWithError((std::string(what) + " disagrees with lowpair: " + std::to_string(error) + " x size").c_str());
  return true;
}

void fkMujoco(benchmark::State& state, RobotId id) {
  MujocoFixture& f = fixture(id);
  if (rejected(state, f.fk_error, "MuJoCo FK")) return;
  int k = 0;
  for (auto _ : state) {
    f.load(k);
    mj_kinematics(f.m.get(), f.d.get());
    benchmark::DoNotOptimize(f.d->site_xpos);
    benchmark::ClobberMemory();
    k = (k + 1) & (kPool - 1);
  }
}

void jacobianMujoco(benchmark::State& state, RobotId id) {
  MujocoFixture& f = fixture(id);
  if (rejected(state, f.jac_error, "MuJoCo Jacobian")) return;
  int k = 0;
  for (auto _ : state) {
    f.load(k);
    mj_kinematics(f.m.get(), f.d.get());
    mj_comPos(f.m.get(), f.d.get());
    mj_jacSite(f.m.get(), f.d.get(), f.jacp.data(), f.jacr.data(), f.site);
    benchmark::DoNotOptimize(f.jacp.data());
    benchmark::ClobberMemory();
    k = (k + 1) & (kPool - 1);
  }
}

}  // namespace

std::string registerMujocoBenchmarks(RobotId id, const std::string& name) {
  if (id == RobotId::User) {
    const RobotCase& r = robotCase(id);
    std::error_code ec;
    if (!std::filesystem::is_regular_file(r.mjcf, ec)) return "no " + r.mjcf + " (the robot as MJCF, with a site named tool)";
    try {
      const MujocoFixture& f = fixture(id);
      const double error = std::max(f.fk_error, f.jac_error);
      if (error > kAgree) {
        return r.mjcf + ": disagrees with the robot file by " + std::to_string(error) +
               " x size (FK or Jacobian at site tool, qpos = qpos0 + x; the same units?)";
      }
    } catch (const std::exception& e) {
      return e.what();
    }
  }
  benchmark::RegisterBenchmark(("BM_Fk_Mujoco_" + name).c_str(), fkMujoco, id);
  benchmark::RegisterBenchmark(("BM_Jacobian_Mujoco_" + name).c_str(), jacobianMujoco, id);
  return "";
}

}  // namespace lowpair_bench
