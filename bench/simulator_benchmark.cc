// Speed of the hot paths: one M,h evaluation, one right-hand side with contact, and whole runs
// (10 s standing with pd_hold, a passive fall with contacts) with each integrator, reported as
// the real-time factor (rtf = simulated s per wall s) and microseconds per control period.
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

}  // namespace
}  // namespace rabbit

BENCHMARK_MAIN();
