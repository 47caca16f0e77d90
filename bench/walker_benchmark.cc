// The closed loop: the Fuzzy-CMAC walker against the pragmatic rules on the same
// scenario, robot and simulator (the walker's cost is the only difference), the controller's cost
// per control period, the gait pattern in the chapter's frame and in the thigh frame (and the
// multi_cmac baseline's query and training), and the whole default suite on 1 and 2 threads. Run
// with --benchmark_enable_random_interleaving=true so the pairs alternate (this machine's speed
// drifts).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <thread>

#include "rabbit/scenario/batch.h"
#include "rabbit/scenario/run.h"
#include "rabbit/scenario/suite.h"

namespace rabbit {
namespace {

const std::string kSuite = std::string(RABBIT_SOURCE_DIR) + "/scenarios/paper.toml";

const Suite& Paper() {
  static const Suite suite = LoadSuite(kSuite);
  return suite;
}

const Scenario& Named(const std::string& name) {
  for (const Scenario& s : Paper().scenarios) {
    if (s.name == name) return s;
  }
  throw std::runtime_error("no scenario " + name);
}

std::shared_ptr<const GaitLibrary> Library() {
  static const std::shared_ptr<const GaitLibrary> library =
      LoadGaitLibrary(Paper().scenarios[0].pattern);
  return library;
}

// 30 s of flat walking at 0.6 m/s (scenario "flat"), recording nothing.
void WalkFlat(benchmark::State& state, const char* variant) {
  Scenario s = Named("flat");
  s.options.record_every = 0;
  const std::shared_ptr<const GaitLibrary> library = Library();
  double simulated = 0.0;
  long steps = 0;
  IntegratorStats stats;
  long periods = 0, events = 0;
  for (auto _ : state) {
    const RunOutput run = RunScenario(s, variant, library.get());
    simulated += run.sim.t_end;
    steps += run.metrics.steps;
    stats = run.sim.integrator;
    periods = run.sim.num_periods;
    events = run.sim.num_events;
    benchmark::DoNotOptimize(run.metrics.distance);
  }
  state.counters["rtf"] = benchmark::Counter(simulated, benchmark::Counter::kIsRate);
  state.counters["s_per_period"] = benchmark::Counter(  // CPU s per control period
      static_cast<double>(periods) * static_cast<double>(state.iterations()),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["steps"] = static_cast<double>(steps) / static_cast<double>(state.iterations());
  // Per control period of the last run: integrator steps, right-hand sides, guard evaluations,
  // restarts (torque changes and contact events) and contact events.
  const double n = static_cast<double>(std::max(1L, periods));
  state.counters["int_steps_per_period"] = static_cast<double>(stats.steps) / n;
  state.counters["rhs_per_period"] = static_cast<double>(stats.rhs_evals) / n;
  state.counters["guards_per_period"] = static_cast<double>(stats.root_evals) / n;
  state.counters["restarts_per_period"] = static_cast<double>(stats.reinits) / n;
  state.counters["events_per_period"] = static_cast<double>(events) / n;
}
void BM_WalkFlatFuzzyCmac(benchmark::State& state) { WalkFlat(state, "fuzzy_cmac"); }
void BM_WalkFlatPragmatic(benchmark::State& state) { WalkFlat(state, "pragmatic"); }
BENCHMARK(BM_WalkFlatFuzzyCmac)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_WalkFlatPragmatic)->Unit(benchmark::kMillisecond);

// One control period of the walker (gait meter, gait pattern, four PD laws) in mid-swing.
void BM_WalkerControlPeriod(benchmark::State& state) {
  const Scenario& s = Named("flat");
  WalkerParams p = s.walker;
  p.warmup_steps = 0;
  p.log_every = 0;
  // The gaits' own rules and step lengths, as RunScenario gives them to the walker.
  p.gait_rules.clear();
  p.gait_l_steps.clear();
  for (const GaitRecord& g : Library()->gaits) {
    p.gait_rules.push_back(g.spec.rules);
    p.gait_l_steps.push_back(g.measured.l_step);
  }
  FuzzyCmacWalker walker(p, Library()->pattern, s.velocity, 0);
  Observation obs;
  obs.q << 0.1, 0.86, 0.15, 0.2, -0.05, -0.1, -0.6;
  obs.qd << 0.6, 0.0, 0.0, -1.0, 0.0, 2.0, 1.0;
  obs.foot_contact = {true, false};
  obs.foot_pos = {Vec2(0.1, 0.0), Vec2(-0.1, 0.05)};
  Terrain terrain;
  obs.terrain = &terrain;
  for (auto _ : state) {
    obs.t += 1e-3;
    benchmark::DoNotOptimize(walker.Compute(obs));
  }
}
BENCHMARK(BM_WalkerControlPeriod);

void GaitPatternQuery(benchmark::State& state, bool thigh) {
  FuzzyCmac pattern = Library()->pattern;
  pattern.SetContext(0.56, 1.0);  // two gaits blended
  double e = -0.2;
  for (auto _ : state) {
    e = e > 0.3 ? -0.2 : e + 1e-4;
    benchmark::DoNotOptimize(thigh ? pattern.QueryThigh(e) : pattern.Query(e));
  }
}
void BM_GaitPatternQueryChapterFrame(benchmark::State& state) { GaitPatternQuery(state, false); }
void BM_GaitPatternQueryThighFrame(benchmark::State& state) { GaitPatternQuery(state, true); }
BENCHMARK(BM_GaitPatternQueryChapterFrame);
BENCHMARK(BM_GaitPatternQueryThighFrame);

// The multi_cmac baseline: its query (four multi-input CMACs at (th_st, V_M, d_obs), thigh frame)
// beside the Fuzzy-CMAC's above, and its training on the Fuzzy-CMAC with the default options.
void BM_MultiCmacPatternQuery(benchmark::State& state) {
  static const std::shared_ptr<const MultiCmacPattern> pattern =
      MultiCmacBaseline(Named("flat"), *Library());
  double e = -0.2;
  for (auto _ : state) {
    e = e > 0.3 ? -0.2 : e + 1e-4;
    benchmark::DoNotOptimize(pattern->Query(e, 0.56, 1.0));
  }
}
BENCHMARK(BM_MultiCmacPatternQuery);

void BM_MultiCmacPatternTraining(benchmark::State& state) {
  const Scenario& s = Named("flat");
  std::vector<double> velocities;
  for (const GaitRecord& g : Library()->gaits) velocities.push_back(g.measured.v_m);
  const MultiCmacPatternDomain domain =
      TeacherDomain(Library()->pattern, velocities, s.walker.thigh_frame, s.walker.d_obs_max,
                    s.multi_cmac.v_m_margin);
  for (auto _ : state) {
    benchmark::DoNotOptimize(TrainMultiCmacPattern(Library()->pattern, domain, s.multi_cmac));
  }
}
BENCHMARK(BM_MultiCmacPatternTraining)->Unit(benchmark::kMillisecond)->Iterations(3);

// The whole default suite (every scenario and baseline, no files written) on N threads.
void BM_PaperSuite(benchmark::State& state) {
  const std::vector<BatchJob> jobs = PlanBatch(Paper(), "");
  double simulated = 0.0;
  for (auto _ : state) {
    RunBatch(jobs, static_cast<int>(state.range(0)), nullptr,
             [&simulated](size_t, RunOutput&& run) { simulated += run.sim.t_end; });
  }
  const double runs = static_cast<double>(jobs.size() * state.iterations());
  state.counters["runs_per_min"] = benchmark::Counter(60.0 * runs, benchmark::Counter::kIsRate);
  state.counters["rtf"] = benchmark::Counter(simulated, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_PaperSuite)->Arg(1)->Arg(2)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

}  // namespace
}  // namespace rabbit

BENCHMARK_MAIN();
