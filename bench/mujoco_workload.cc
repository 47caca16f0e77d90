// The peer of a whole `rabbit run` process for bench/compare.sh: MuJoCo 2.2 stepping the same
// robot (tests/mujoco_model.h builds the MJCF from the same parameters) for a given simulated time
// at the controller's 1 ms rate, Euler, default soft contacts (friction 0.8), with the pd_hold law
// of scenarios/standing_pd_hold.toml and the actuator saturation applied through qfrc_applied at
// every step, restarted from that scenario's initial state every scenario duration (10 s).
//
//   mujoco_workload SECONDS [SCENARIO.toml]
//
// Prints the simulated time, the steps and the hip height at the end (so that a run that went
// wrong shows). The process's CPU time is what compare.sh measures.
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "mujoco_model.h"
#include "rabbit/contact/actuator.h"
#include "rabbit/scenario/scenario.h"

#ifndef RABBIT_SOURCE_DIR
#define RABBIT_SOURCE_DIR "."
#endif

namespace rabbit {
namespace {

int Main(int argc, char** argv) {
  if (argc < 2 || argc > 3) {
    std::fprintf(stderr, "usage: %s SECONDS [SCENARIO.toml]\n", argv[0]);
    return 2;
  }
  char* end = nullptr;
  const double seconds = std::strtod(argv[1], &end);
  if (end == argv[1] || *end != '\0' || !(seconds > 0.0) || seconds > 1e6) {
    std::fprintf(stderr, "%s: SECONDS must be a number in (0, 1e6], got \"%s\"\n", argv[0],
                 argv[1]);
    return 2;
  }
  const std::string path =
      argc == 3 ? std::string(argv[2])
                : std::string(RABBIT_SOURCE_DIR) + "/scenarios/standing_pd_hold.toml";
  const Scenario scenario = LoadScenario(path);
  mujoco_ref::MujocoModelOptions options;
  options.ground = true;
  options.integrator = "Euler";
  options.timestep = scenario.options.control_period;
  options.energy = false;
  std::string error;
  mujoco_ref::ModelPtr m = mujoco_ref::LoadRabbitMujocoModel(scenario.model, options, &error);
  if (!m) {
    std::fprintf(stderr, "%s: %s\n", argv[0], error.c_str());
    return 1;
  }
  mujoco_ref::DataPtr d(mj_makeData(m.get()));
  const long total = std::lround(seconds / m->opt.timestep);
  const long per_run = std::max(1L, std::lround(scenario.options.duration / m->opt.timestep));
  const PdHoldParams& pd = scenario.pd_hold;
  double simulated = 0.0;
  for (long k = 0; k < total; ++k) {
    if (k % per_run == 0) {
      simulated += d->time;
      mj_resetData(m.get(), d.get());
      mujoco_ref::SetMujocoState(m.get(), d.get(), scenario.q0, scenario.qd0);
    }
    for (int j = 0; j < kNumJoints; ++j) {
      const int i = 3 + j;
      const double tau = pd.kp[j] * (pd.target[j] - d->qpos[i]) - pd.kd[j] * d->qvel[i];
      SaturationRegion region;
      d->qfrc_applied[i] = SaturateTorque(scenario.actuator, tau, d->qvel[i], &region);
    }
    mj_step(m.get(), d.get());
  }
  simulated += d->time;
  std::printf("simulated_s %.3f steps %ld hip_y_end_m %.4f\n", simulated, total, d->qpos[kY]);
  return 0;
}

}  // namespace
}  // namespace rabbit

int main(int argc, char** argv) {
  try {
    return rabbit::Main(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", argv[0], e.what());
    return 2;
  }
}
