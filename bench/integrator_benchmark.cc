// Work-precision of the integrators on the shipped scenarios: for each integrator (CVODE BDF,
// CVODE Adams, ARKODE explicit Runge-Kutta of order 2..5) and tolerance, the real-time factor and
// the largest deviation of q from a reference run (CVODE BDF at rtol 1e-11), sample by sample.
// This is the measurement behind the default integrator (bench/README.md).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <map>
#include <string>

#include "rabbit/scenario/scenario.h"
#include "rabbit/sim/simulator.h"

#ifndef RABBIT_SOURCE_DIR
#define RABBIT_SOURCE_DIR "."
#endif

namespace rabbit {
namespace {

const char* const kScenarios[] = {"standing_pd_hold.toml", "passive_fall.toml", "drop_2cm.toml"};

struct Loaded {
  Scenario scenario;
  std::unique_ptr<Model> model;
  SimSetup setup;
  SimResult reference;
};

const Loaded& Load(int index) {
  static std::map<int, Loaded> cache;
  auto it = cache.find(index);
  if (it != cache.end()) return it->second;
  Loaded& l = cache[index];
  l.scenario = LoadScenario(std::string(RABBIT_SOURCE_DIR) + "/scenarios/" + kScenarios[index]);
  l.model = std::make_unique<Model>(l.scenario.model);
  l.setup = MakeSimSetup(l.scenario, l.model.get());
  l.setup.options.duration = std::min(l.setup.options.duration, 2.0);
  SimSetup ref = l.setup;
  ref.options.integrator.kind = IntegratorKind::kCvodeBdf;
  ref.options.integrator.rtol = 1e-11;
  ref.options.integrator.atol = 1e-13;
  ref.options.integrator.max_steps_per_call = 1000000;
  auto controller = MakeController(l.scenario);
  l.reference = Simulate(ref, l.scenario.q0, l.scenario.qd0, controller.get());
  return l;
}

// Args: scenario index, integrator kind, order, -log10(rtol), restart at samples (0/1).
void BM_WorkPrecision(benchmark::State& state) {
  const Loaded& l = Load(static_cast<int>(state.range(0)));
  SimSetup setup = l.setup;
  setup.options.integrator.kind = static_cast<IntegratorKind>(state.range(1));
  setup.options.integrator.order = static_cast<int>(state.range(2));
  setup.options.integrator.rtol = std::pow(10.0, -static_cast<double>(state.range(3)));
  setup.options.integrator.atol = setup.options.integrator.rtol * 1e-2;
  setup.options.restart_at_samples = state.range(4) != 0;
  SimResult r;
  double simulated = 0.0;
  for (auto _ : state) {
    auto controller = MakeController(l.scenario);
    r = Simulate(setup, l.scenario.q0, l.scenario.qd0, controller.get());
    simulated += r.t_end;
  }
  double error = 0.0;
  const size_t n = std::min(r.samples.size(), l.reference.samples.size());
  for (size_t i = 0; i < n; ++i) {
    error = std::max(error, (r.samples[i].q - l.reference.samples[i].q).cwiseAbs().maxCoeff());
  }
  state.SetLabel(std::string(kScenarios[state.range(0)]) + " " +
                 IntegratorName(setup.options.integrator.kind) + " " + OutcomeName(r.outcome));
  state.counters["rtf"] = benchmark::Counter(simulated, benchmark::Counter::kIsRate);
  state.counters["max_q_error"] = error;
  state.counters["rhs_per_period"] =
      static_cast<double>(r.integrator.rhs_evals) / static_cast<double>(r.num_periods);
}

void Arguments(benchmark::internal::Benchmark* b) {
  for (int scenario = 0; scenario < 3; ++scenario) {
    for (int digits : {4, 5, 6, 8}) {  // 5: the default (rtol 1e-5, atol 1e-7)
      b->Args({scenario, static_cast<int>(IntegratorKind::kCvodeBdf), 0, digits, 1});
      b->Args({scenario, static_cast<int>(IntegratorKind::kCvodeAdams), 0, digits, 1});
      for (int order = 2; order <= 5; ++order) {
        b->Args({scenario, static_cast<int>(IntegratorKind::kArkodeErk), order, digits, 1});
      }
    }
    // Without restarts where the held torques change (SimOptions::restart_at_samples).
    for (int digits : {6, 8}) {
      b->Args({scenario, static_cast<int>(IntegratorKind::kCvodeBdf), 0, digits, 0});
      b->Args({scenario, static_cast<int>(IntegratorKind::kArkodeErk), 3, digits, 0});
    }
  }
  b->ArgNames({"scenario", "integrator", "order", "digits", "restart"});
}
BENCHMARK(BM_WorkPrecision)->Apply(Arguments)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace rabbit

BENCHMARK_MAIN();
