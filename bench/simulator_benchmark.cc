// Speed of the hot paths: one M,h evaluation, one right-hand side with contact, one foot's contact
// force (flat and sloped ground), and whole runs (10 s standing with pd_hold, a passive fall with
// contacts) with each integrator, and standing on a ground profile, reported as the real-time
// factor (rtf = simulated s per wall s) and microseconds per control period.
#include <benchmark/benchmark.h>

#include <random>
#include <string>

#include "rabbit/model/model.h"
#include "rabbit/scenario/scenario.h"
#include "rabbit/sim/simulator.h"

#ifndef RABBIT_SOURCE_DIR
#define RABBIT_SOURCE_DIR "."
#endif

namespace rabbit {
namespace {

std::vector<std::pair<Vec7, Vec7>> RandomStates(int n) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<std::pair<Vec7, Vec7>> states;
  for (int i = 0; i < n; ++i) {
    Vec7 q, qd;
    for (int k = 0; k < kNq; ++k) {
      q[k] = u(rng);
      qd[k] = 3 * u(rng);
    }
    q[kY] += 1.0;
    states.emplace_back(q, qd);
  }
  return states;
}

void BM_ComputeDynamics(benchmark::State& state) {
  const Model model{ModelParams{}};
  Data data;
  const auto states = RandomStates(64);
  size_t i = 0;
  for (auto _ : state) {
    const auto& [q, qd] = states[i++ & 63];
    ComputeDynamics(model, q, qd, &data);
    benchmark::DoNotOptimize(data.h);
  }
}
BENCHMARK(BM_ComputeDynamics);

void BM_ForwardDynamicsWithFeet(benchmark::State& state) {
  const Model model{ModelParams{}};
  Data data;
  const auto states = RandomStates(64);
  size_t i = 0;
  for (auto _ : state) {
    const auto& [q, qd] = states[i++ & 63];
    ComputeAbsoluteDynamics(model, q, qd, &data);
    ComputeFootKinematics(model, q, qd, &data);
    Vec7 Q = Vec7::Zero();
    for (int leg = 0; leg < kNumLegs; ++leg) {
      AddFootForce(model, data, leg, Vec2(10.0, 300.0), &Q);
    }
    SolveForAcceleration(model, Q, &data);
    benchmark::DoNotOptimize(data.qdd);
  }
}
BENCHMARK(BM_ForwardDynamicsWithFeet);

// The same with rotor inertia, which takes the joint-space Cholesky path.
void BM_ForwardDynamicsJointSpaceCholesky(benchmark::State& state) {
  ModelParams params;
  params.rotor_inertia = 3.32e-4;
  const Model model(params);
  Data data;
  const auto states = RandomStates(64);
  size_t i = 0;
  for (auto _ : state) {
    const auto& [q, qd] = states[i++ & 63];
    ForwardDynamics(model, q, qd, Vec7::Zero(), &data);
    benchmark::DoNotOptimize(data.qdd);
  }
}
BENCHMARK(BM_ForwardDynamicsJointSpaceCholesky);

// One foot's contact force (the right-hand side's per-foot cost): sticking 2 mm deep, on flat
// ground (the default terrain) and on a 5 deg segment of a ground profile.
void BM_FootForce(benchmark::State& state) {
  const ContactParams params;
  Terrain terrain;
  FootContactState foot;
  foot.mode = ContactMode::kStick;
  foot.anchor_x = 0.5;
  double y = -0.002;
  if (state.range(0) != 0) {
    terrain.ground = GroundProfile({{0.0, 5.0 * M_PI / 180.0}});
    foot.segment = 1;
    y += terrain.GroundHeight(0.5);
  }
  const auto states = RandomStates(64);
  size_t i = 0;
  for (auto _ : state) {
    const auto& [q, qd] = states[i++ & 63];
    const Vec2 pos(0.5 + 1e-4 * q[kQ0], y + 1e-4 * q[kQ11]), vel(0.01 * qd[kX], 0.01 * qd[kY]);
    benchmark::DoNotOptimize(ComputeFootForce(params, terrain, foot, pos, vel));
  }
}
BENCHMARK(BM_FootForce)->Arg(0)->Arg(1)->ArgName("sloped");

// Runs a shipped scenario with the given integrator; counters: rtf, us per control period,
// integrator steps and rhs evaluations per control period.
void RunScenario(benchmark::State& state, const char* file, IntegratorKind kind) {
  const Scenario scenario = LoadScenario(std::string(RABBIT_SOURCE_DIR) + "/scenarios/" + file);
  const Model model(scenario.model);
  SimSetup setup = MakeSimSetup(scenario, &model);
  setup.options.integrator.kind = kind;
  double simulated = 0.0;
  long periods = 0, steps = 0, rhs = 0, roots = 0;
  for (auto _ : state) {
    auto controller = MakeController(scenario);
    const SimResult r = Simulate(setup, scenario.q0, scenario.qd0, controller.get());
    simulated += r.t_end;
    periods += r.num_periods;
    steps += r.integrator.steps;
    rhs += r.integrator.rhs_evals;
    roots += r.integrator.root_evals;
  }
  state.counters["rtf"] = benchmark::Counter(simulated, benchmark::Counter::kIsRate);
  state.counters["us_per_period"] =
      benchmark::Counter(static_cast<double>(periods) * 1e-6,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["steps_per_period"] = static_cast<double>(steps) / static_cast<double>(periods);
  state.counters["rhs_per_period"] = static_cast<double>(rhs) / static_cast<double>(periods);
  state.counters["roots_per_period"] = static_cast<double>(roots) / static_cast<double>(periods);
}

void BM_Standing10s(benchmark::State& state) {
  RunScenario(state, "standing_pd_hold.toml", static_cast<IntegratorKind>(state.range(0)));
}
BENCHMARK(BM_Standing10s)
    ->Arg(static_cast<int>(IntegratorKind::kCvodeBdf))
    ->Arg(static_cast<int>(IntegratorKind::kCvodeAdams))
    ->Arg(static_cast<int>(IntegratorKind::kArkodeErk))
    ->ArgName("integrator(0=cvode,1=cvode-adams,2=arkode)")
    ->Unit(benchmark::kMillisecond);

void BM_PassiveFall(benchmark::State& state) {
  RunScenario(state, "passive_fall.toml", static_cast<IntegratorKind>(state.range(0)));
}
BENCHMARK(BM_PassiveFall)
    ->Arg(static_cast<int>(IntegratorKind::kCvodeBdf))
    ->Arg(static_cast<int>(IntegratorKind::kCvodeAdams))
    ->Arg(static_cast<int>(IntegratorKind::kArkodeErk))
    ->ArgName("integrator(0=cvode,1=cvode-adams,2=arkode)")
    ->Unit(benchmark::kMillisecond);

// Standing (as BM_Standing10s, ARKODE) on a ground profile whose breakpoint is 50 m behind: one
// 0 deg or 5 deg segment under the feet, segment guards on. Compare with BM_Standing10s/2 for the
// cost of the profile.
void BM_Standing10sOnProfile(benchmark::State& state) {
  Scenario scenario =
      LoadScenario(std::string(RABBIT_SOURCE_DIR) + "/scenarios/standing_pd_hold.toml");
  const double a = static_cast<double>(state.range(0)) * M_PI / 180.0;
  scenario.terrain.ground = GroundProfile({{-50.0, a}});
  if (state.range(0) != 0) {
    // The stance rotated onto the incline (feet on it; the walking frame's pitch).
    Vec7& q = scenario.q0;
    const Vec2 hip =
        q[kX] * Vec2(std::cos(a), -std::sin(a)) + q[kY] * Vec2(std::sin(a), std::cos(a));
    q[kX] = hip.x();
    q[kY] = hip.y();
    q[kQ0] += a;
  }
  const Model model(scenario.model);
  SimSetup setup = MakeSimSetup(scenario, &model);
  double simulated = 0.0;
  long periods = 0, steps = 0, events = 0;
  for (auto _ : state) {
    auto controller = MakeController(scenario);
    const SimResult r = Simulate(setup, scenario.q0, scenario.qd0, controller.get());
    if (r.outcome != Outcome::kCompleted) state.SkipWithError(r.reason.c_str());
    simulated += r.t_end;
    periods += r.num_periods;
    steps += r.integrator.steps;
    events += r.num_events;
  }
  state.counters["steps_per_period"] = static_cast<double>(steps) / static_cast<double>(periods);
  state.counters["events_per_run"] =
      static_cast<double>(events) / static_cast<double>(state.iterations());
  state.counters["rtf"] = benchmark::Counter(simulated, benchmark::Counter::kIsRate);
  state.counters["us_per_period"] =
      benchmark::Counter(static_cast<double>(periods) * 1e-6,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_Standing10sOnProfile)
    ->Arg(0)
    ->Arg(5)
    ->ArgName("slope_deg")
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace rabbit

BENCHMARK_MAIN();
