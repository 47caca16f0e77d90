// rabbit-gait against MuJoCo on the same robot (tests/mujoco_model.h builds the MJCF):
//   Standing/*  10 s standing with pd_hold (scenarios/standing_pd_hold.toml): our Simulate
//               (SUNDIALS, compliant contact of docs/design/model.md) versus MuJoCo with a ground
//               plane, soft contacts (defaults, friction 0.8), timestep 1 ms, the same PD law and
//               actuator saturation applied through qfrc_applied at every step from the same
//               initial state (Euler and RK4; and Euler with 10 noslip iterations, since MuJoCo's
//               default soft contacts let the feet creep apart, see foot_slip_mm);
//   Swing/*     5 s contact-free, torque-free swing (scenarios/swing_free.toml), with the relative
//               energy drift max_t |E(t) - E(0)| / |E(0)| (energy_drift) and at the end
//               (energy_drift_end), E sampled every 1 ms: ours from SimResult via TotalEnergy,
//               MuJoCo's from mj_energyPos + mj_energyVel (computed in an untimed pass, so the
//               timed loop is plain mj_step); q_end_vs_rabbit = max |q_MuJoCo(5 s) - q_ours(5 s)|;
//   PassiveFall/*
//               torque-free collapse from a leaning standing pose (scenarios/passive_fall.toml):
//               our Simulate, which ends when the robot falls (SimResult::t_end), versus MuJoCo
//               with the ground plane of Standing/* (Euler and RK4, timestep 1 ms, zero torques)
//               from the same initial state for the same simulated time (our t_end, computed once
//               in an untimed run); hip_y_end_mm = hip height at the end, to see that both fell
//               alike, and t_end_s = the simulated time of the run;
//   Dynamics/*  one ComputeDynamics (M and h) versus MuJoCo's M and qfrc_bias (kinematics, crb,
//               rne), and one ForwardDynamics versus one mj_forward, on the contact-free model at
//               a random state.
// Counter rtf = simulated seconds per wall-clock second. The ours/MuJoCo pairs are registered next
// to each other, and unless told otherwise the program runs 3 repetitions with random interleaving
// (--benchmark_enable_random_interleaving), so both sides see the same machine conditions; pass
// --benchmark_repetitions=1 for a quick run.
#include <benchmark/benchmark.h>
#include <mujoco/mujoco.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "mujoco_model.h"
#include "rabbit/contact/actuator.h"
#include "rabbit/model/model.h"
#include "rabbit/scenario/scenario.h"
#include "rabbit/sim/simulator.h"

#ifndef RABBIT_SOURCE_DIR
#define RABBIT_SOURCE_DIR "."
#endif

namespace rabbit {
namespace {

using Clock = std::chrono::steady_clock;
using mujoco_ref::DataPtr;
using mujoco_ref::ModelPtr;
using mujoco_ref::MujocoModelOptions;

Scenario LoadShippedScenario(const char* name) {
  return LoadScenario(std::string(RABBIT_SOURCE_DIR) + "/scenarios/" + name);
}

double Seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

ModelPtr LoadMujoco(const ModelParams& params, const MujocoModelOptions& options) {
  std::string error;
  ModelPtr m = mujoco_ref::LoadRabbitMujocoModel(params, options, &error);
  if (!m) throw std::runtime_error(error);
  return m;
}

// Mirror of PdHoldController + the simulator's actuator saturation, on MuJoCo's state.
void ApplyPdHold(const Scenario& scenario, mjData* d) {
  const PdHoldParams& pd = scenario.pd_hold;
  for (int j = 0; j < kNumJoints; ++j) {
    const int i = 3 + j;
    const double tau = pd.kp[j] * (pd.target[j] - d->qpos[i]) - pd.kd[j] * d->qvel[i];
    SaturationRegion region;
    d->qfrc_applied[i] = SaturateTorque(scenario.actuator, tau, d->qvel[i], &region);
  }
}

// Total (kinetic + potential) energy of MuJoCo's current state.
double MujocoEnergy(const mjModel* m, mjData* d) {
  mj_forward(m, d);
  mj_energyPos(m, d);
  mj_energyVel(m, d);
  return d->energy[0] + d->energy[1];
}

struct Drift {
  double max = 0.0, end = 0.0;
};
Drift EnergyDrift(const std::vector<double>& energy) {
  Drift drift;
  const double e0 = energy.front();
  for (double e : energy) drift.max = std::max(drift.max, std::abs(e - e0) / std::abs(e0));
  drift.end = std::abs(energy.back() - e0) / std::abs(e0);
  return drift;
}

// Times our run of a scenario over the benchmark's iterations; false (with the benchmark marked
// as failed) when a run does not end with the expected outcome. *rtf: simulated s per wall s.
bool TimeRabbitRuns(benchmark::State& state, const Scenario& scenario, const SimSetup& setup,
                    Outcome expected, SimResult* result, double* rtf) {
  double wall = 0.0, simulated = 0.0;
  for (auto _ : state) {
    std::unique_ptr<Controller> controller = MakeController(scenario);
    const Clock::time_point start = Clock::now();
    *result = Simulate(setup, scenario.q0, scenario.qd0, controller.get());
    wall += Seconds(Clock::now() - start);
    simulated += result->t_end;
    if (result->outcome != expected) {
      const std::string error = std::string("run ended ") + OutcomeName(result->outcome) +
                                " (expected " + OutcomeName(expected) + "): " + result->reason;
      state.SkipWithError(error.c_str());
      return false;
    }
  }
  *rtf = simulated / wall;
  return !result->samples.empty();
}

// ---------------------------------------------------------------------------------------------
// Standing with pd_hold, 10 s.

void BM_Standing_Rabbit(benchmark::State& state) {
  const Scenario scenario = LoadShippedScenario("standing_pd_hold.toml");
  const Model model(scenario.model);
  const SimSetup setup = MakeSimSetup(scenario, &model);
  SimResult result;
  double rtf = 0.0;
  if (!TimeRabbitRuns(state, scenario, setup, Outcome::kCompleted, &result, &rtf)) return;
  const SimSample& last = result.samples.back();
  const SimSample& first = result.samples.front();
  state.counters["rtf"] = rtf;
  state.counters["hip_y_end_mm"] = 1e3 * last.q[kY];
  state.counters["hip_dy_mm"] = 1e3 * (last.q[kY] - first.q[kY]);
  double slip = 0.0;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    slip = std::max(slip, std::abs(last.foot_pos[leg].x() - first.foot_pos[leg].x()));
  }
  state.counters["foot_slip_mm"] = 1e3 * slip;
  state.counters["steps_per_s"] = static_cast<double>(result.integrator.steps) / result.t_end;
}

void BM_Standing_MuJoCo(benchmark::State& state, const std::string& integrator,
                        int noslip_iterations) {
  const Scenario scenario = LoadShippedScenario("standing_pd_hold.toml");
  MujocoModelOptions options;
  options.ground = true;
  options.integrator = integrator;
  options.noslip_iterations = noslip_iterations;
  options.timestep = 1e-3;
  options.energy = false;
  ModelPtr m = LoadMujoco(scenario.model, options);
  DataPtr d(mj_makeData(m.get()));
  const Model model(scenario.model);
  const int steps = static_cast<int>(std::lround(scenario.options.duration / m->opt.timestep));
  const int site[kNumLegs] = {mj_name2id(m.get(), mjOBJ_SITE, "foot1"),
                              mj_name2id(m.get(), mjOBJ_SITE, "foot2")};
  double wall = 0.0, simulated = 0.0;
  for (auto _ : state) {
    mj_resetData(m.get(), d.get());
    mujoco_ref::SetMujocoState(m.get(), d.get(), scenario.q0, scenario.qd0);
    const Clock::time_point start = Clock::now();
    for (int k = 0; k < steps; ++k) {
      ApplyPdHold(scenario, d.get());
      mj_step(m.get(), d.get());
    }
    wall += Seconds(Clock::now() - start);
    simulated += d->time;
    benchmark::DoNotOptimize(d->qpos[0]);
  }
  mj_forward(m.get(), d.get());
  state.counters["rtf"] = simulated / wall;
  state.counters["hip_y_end_mm"] = 1e3 * d->qpos[kY];
  state.counters["hip_dy_mm"] = 1e3 * (d->qpos[kY] - scenario.q0[kY]);
  double slip = 0.0;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const double x0 = FootPosition(model, scenario.q0, leg).x();
    slip = std::max(slip, std::abs(d->site_xpos[3 * site[leg]] - x0));
  }
  state.counters["foot_slip_mm"] = 1e3 * slip;
  state.counters["steps_per_s"] = 1.0 / m->opt.timestep;
}

// ---------------------------------------------------------------------------------------------
// Contact-free, torque-free swing, 5 s.

void BM_Swing_Rabbit(benchmark::State& state) {
  const Scenario scenario = LoadShippedScenario("swing_free.toml");
  const Model model(scenario.model);
  const SimSetup setup = MakeSimSetup(scenario, &model);
  SimResult result;
  double rtf = 0.0;
  if (!TimeRabbitRuns(state, scenario, setup, Outcome::kCompleted, &result, &rtf)) return;
  if (result.samples.size() < 2) return;
  std::vector<double> energy;
  energy.reserve(result.samples.size());
  for (const SimSample& s : result.samples) energy.push_back(TotalEnergy(s));
  const Drift drift = EnergyDrift(energy);
  state.counters["rtf"] = rtf;
  state.counters["energy_drift"] = drift.max;
  state.counters["energy_drift_end"] = drift.end;
  state.counters["E0_J"] = energy.front();
  state.counters["steps_per_s"] = static_cast<double>(result.integrator.steps) / result.t_end;
}

void BM_Swing_MuJoCo(benchmark::State& state, const std::string& integrator) {
  const Scenario scenario = LoadShippedScenario("swing_free.toml");
  MujocoModelOptions options;
  options.integrator = integrator;
  options.timestep = 1e-3;
  options.energy = true;
  ModelPtr m = LoadMujoco(scenario.model, options);
  DataPtr d(mj_makeData(m.get()));
  const int steps = static_cast<int>(std::lround(scenario.options.duration / m->opt.timestep));

  // Untimed pass: energy after every step (the same trajectory as the timed runs below).
  mj_resetData(m.get(), d.get());
  mujoco_ref::SetMujocoState(m.get(), d.get(), scenario.q0, scenario.qd0);
  std::vector<double> energy{MujocoEnergy(m.get(), d.get())};
  for (int k = 0; k < steps; ++k) {
    mj_step(m.get(), d.get());
    energy.push_back(MujocoEnergy(m.get(), d.get()));
  }
  const Drift drift = EnergyDrift(energy);
  // Where the trajectory ends compared with ours (SUNDIALS, rtol 1e-10).
  const Model model(scenario.model);
  const SimSetup setup = MakeSimSetup(scenario, &model);
  std::unique_ptr<Controller> controller = MakeController(scenario);
  const SimResult ours = Simulate(setup, scenario.q0, scenario.qd0, controller.get());
  const double q_diff =
      (mujoco_ref::MujocoQ(m.get(), d.get()) - ours.samples.back().q).cwiseAbs().maxCoeff();

  m->opt.enableflags &= ~mjENBL_ENERGY;  // timed runs: plain stepping
  double wall = 0.0, simulated = 0.0;
  for (auto _ : state) {
    mj_resetData(m.get(), d.get());
    mujoco_ref::SetMujocoState(m.get(), d.get(), scenario.q0, scenario.qd0);
    const Clock::time_point start = Clock::now();
    for (int k = 0; k < steps; ++k) mj_step(m.get(), d.get());
    wall += Seconds(Clock::now() - start);
    simulated += d->time;
    benchmark::DoNotOptimize(d->qpos[0]);
  }
  state.counters["rtf"] = simulated / wall;
  state.counters["energy_drift"] = drift.max;
  state.counters["energy_drift_end"] = drift.end;
  state.counters["E0_J"] = energy.front();
  state.counters["q_end_vs_rabbit"] = q_diff;
  state.counters["steps_per_s"] = 1.0 / m->opt.timestep;
}

// ---------------------------------------------------------------------------------------------
// Passive fall, until our run detects the fall.

void BM_PassiveFall_Rabbit(benchmark::State& state) {
  const Scenario scenario = LoadShippedScenario("passive_fall.toml");
  const Model model(scenario.model);
  const SimSetup setup = MakeSimSetup(scenario, &model);
  SimResult result;
  double rtf = 0.0;
  if (!TimeRabbitRuns(state, scenario, setup, Outcome::kFell, &result, &rtf)) return;
  state.counters["rtf"] = rtf;
  state.counters["hip_y_end_mm"] = 1e3 * result.samples.back().q[kY];
  state.counters["t_end_s"] = result.t_end;
  state.counters["steps_per_s"] = static_cast<double>(result.integrator.steps) / result.t_end;
}

// Our passive fall, run once untimed: its t_end is how long the MuJoCo runs simulate.
const SimResult& PassiveFallReference() {
  static const SimResult result = [] {
    const Scenario scenario = LoadShippedScenario("passive_fall.toml");
    const Model model(scenario.model);
    const SimSetup setup = MakeSimSetup(scenario, &model);
    std::unique_ptr<Controller> controller = MakeController(scenario);
    return Simulate(setup, scenario.q0, scenario.qd0, controller.get());
  }();
  return result;
}

void BM_PassiveFall_MuJoCo(benchmark::State& state, const std::string& integrator) {
  const Scenario scenario = LoadShippedScenario("passive_fall.toml");
  const SimResult& ours = PassiveFallReference();
  if (ours.outcome != Outcome::kFell) {
    const std::string error =
        std::string("our run did not fall: ") + OutcomeName(ours.outcome) + " " + ours.reason;
    state.SkipWithError(error.c_str());
    return;
  }
  MujocoModelOptions options;
  options.ground = true;
  options.integrator = integrator;
  options.timestep = 1e-3;
  options.energy = false;
  ModelPtr m = LoadMujoco(scenario.model, options);
  DataPtr d(mj_makeData(m.get()));
  const int steps = static_cast<int>(std::lround(ours.t_end / m->opt.timestep));
  double wall = 0.0, simulated = 0.0;
  for (auto _ : state) {
    mj_resetData(m.get(), d.get());
    mujoco_ref::SetMujocoState(m.get(), d.get(), scenario.q0, scenario.qd0);  // zero torques
    const Clock::time_point start = Clock::now();
    for (int k = 0; k < steps; ++k) mj_step(m.get(), d.get());
    wall += Seconds(Clock::now() - start);
    simulated += d->time;
    benchmark::DoNotOptimize(d->qpos[0]);
  }
  state.counters["rtf"] = simulated / wall;
  state.counters["hip_y_end_mm"] = 1e3 * d->qpos[kY];
  state.counters["t_end_s"] = d->time;
  state.counters["steps_per_s"] = 1.0 / m->opt.timestep;
}

// ---------------------------------------------------------------------------------------------
// One evaluation of the dynamics at a random state.

struct RandomState {
  Vec7 q, qd;
  Vec4 tau;
};
RandomState MakeRandomState() {
  std::mt19937 rng(12345u);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  RandomState s;
  for (int i = 0; i < kNq; ++i) {
    s.q[i] = unit(rng);
    s.qd[i] = 3.0 * unit(rng);
  }
  s.q[kY] = 1.0 + 0.1 * unit(rng);
  for (int j = 0; j < kNumJoints; ++j) s.tau[j] = 50.0 * unit(rng);
  return s;
}

void BM_Dynamics_Rabbit_ComputeDynamics(benchmark::State& state) {
  const Model model{ModelParams{}};
  const RandomState s = MakeRandomState();
  Data data;
  for (auto _ : state) {
    ComputeDynamics(model, s.q, s.qd, &data);
    benchmark::DoNotOptimize(data.M.data());
    benchmark::DoNotOptimize(data.h.data());
    benchmark::ClobberMemory();
  }
}

void BM_Dynamics_Rabbit_ForwardDynamics(benchmark::State& state) {
  const Model model{ModelParams{}};
  const RandomState s = MakeRandomState();
  const Vec7 Q = JointTorqueToGeneralized(s.tau);
  Data data;
  for (auto _ : state) {
    benchmark::DoNotOptimize(ForwardDynamics(model, s.q, s.qd, Q, &data));
    benchmark::DoNotOptimize(data.qdd.data());
    benchmark::ClobberMemory();
  }
}

void BM_Dynamics_MuJoCo_Forward(benchmark::State& state) {
  MujocoModelOptions options;
  options.energy = false;
  ModelPtr m = LoadMujoco(ModelParams{}, options);
  DataPtr d(mj_makeData(m.get()));
  const RandomState s = MakeRandomState();
  mujoco_ref::SetMujocoState(m.get(), d.get(), s.q, s.qd);
  for (int j = 0; j < kNumJoints; ++j) d->qfrc_applied[3 + j] = s.tau[j];
  for (auto _ : state) {
    mj_forward(m.get(), d.get());
    benchmark::DoNotOptimize(d->qacc);
    benchmark::ClobberMemory();
  }
}

// M and qfrc_bias only (no factorisation solve of the accelerations): what ComputeDynamics gives.
void BM_Dynamics_MuJoCo_MassAndBias(benchmark::State& state) {
  MujocoModelOptions options;
  options.energy = false;
  ModelPtr m = LoadMujoco(ModelParams{}, options);
  DataPtr d(mj_makeData(m.get()));
  const RandomState s = MakeRandomState();
  mujoco_ref::SetMujocoState(m.get(), d.get(), s.q, s.qd);
  for (auto _ : state) {
    mj_kinematics(m.get(), d.get());
    mj_comPos(m.get(), d.get());
    mj_crb(m.get(), d.get());
    mj_comVel(m.get(), d.get());
    mj_rne(m.get(), d.get(), 0, d->qfrc_bias);
    benchmark::DoNotOptimize(d->qM);
    benchmark::DoNotOptimize(d->qfrc_bias);
    benchmark::ClobberMemory();
  }
}

// Pairs registered side by side (see the file comment about interleaving).
BENCHMARK(BM_Standing_Rabbit)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Standing_MuJoCo, Euler, std::string("Euler"), 0)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_Standing_MuJoCo, RK4, std::string("RK4"), 0)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
// MuJoCo's noslip post-solver removes the soft-contact creep of the feet (foot_slip_mm).
BENCHMARK_CAPTURE(BM_Standing_MuJoCo, Euler_noslip10, std::string("Euler"), 10)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_Swing_Rabbit)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_Swing_MuJoCo, RK4, std::string("RK4"))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_Swing_MuJoCo, Euler, std::string("Euler"))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_PassiveFall_Rabbit)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_PassiveFall_MuJoCo, Euler, std::string("Euler"))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_PassiveFall_MuJoCo, RK4, std::string("RK4"))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_Dynamics_Rabbit_ComputeDynamics);
BENCHMARK(BM_Dynamics_MuJoCo_MassAndBias);
BENCHMARK(BM_Dynamics_Rabbit_ForwardDynamics);
BENCHMARK(BM_Dynamics_MuJoCo_Forward);

}  // namespace
}  // namespace rabbit

// Defaults to 3 interleaved repetitions; any flag given on the command line overrides them.
int main(int argc, char** argv) {
  std::vector<char*> args{argv[0]};
  std::string repetitions = "--benchmark_repetitions=3";
  std::string interleave = "--benchmark_enable_random_interleaving=true";
  args.push_back(repetitions.data());
  args.push_back(interleave.data());
  for (int i = 1; i < argc; ++i) args.push_back(argv[i]);
  int count = static_cast<int>(args.size());
  benchmark::Initialize(&count, args.data());
  if (benchmark::ReportUnrecognizedArguments(count, args.data())) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
