// Tuning throughput: evaluations per second of a tuning job on 1 and 2 threads, against
// its peer, the job's own runs as one plain batch (RunBatch): the tuner's own cost (loading the
// suites under each candidate's overlay, the rounds' barriers, the log) is the difference. The job: 2 searches of CRS2 over the velocity gains, 12 s of each ramp of
// scenarios/tune_ramp.toml per run, 8 evaluations (16 runs). Run with
// --benchmark_enable_random_interleaving=true so the cases alternate (this machine's speed drifts).
// MPI ranks: bench/tune_ranks.sh.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "rabbit/scenario/batch.h"
#include "rabbit/scenario/suite.h"
#include "tune_job.h"
#include "tuner.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;

const fs::path& Dir() {
  static const fs::path dir = [] {
    const fs::path d = fs::temp_directory_path() / ("rabbit_tune_bench_" + std::to_string(getpid()));
    fs::create_directories(d);
    std::ofstream(d / "base.toml") << "[params]\n\"simulation.duration\" = 12\n"
                                      "\"criteria.min_steps\" = 5\n";
    std::ofstream(d / "job.toml")
        << "[job]\nsuites = [\"" << RABBIT_SOURCE_DIR << "/scenarios/tune_ramp.toml\"]\n"
        << "params = \"base.toml\"\nalgorithm = \"crs2\"\npopulation = 4\nmax_evaluations = 8\n"
        << "starts = 2\n[objective]\nspeed_error = 1.0\n[[parameter]]\npath = "
           "\"controller.k_p\"\nlower = 0.0\nupper = 0.6\n[[parameter]]\npath = "
           "\"controller.k_v\"\nlower = 0.0\nupper = 0.4\n";
    return d;
  }();
  return dir;
}

const TuneJob& Job() {
  static const TuneJob job = LoadTuneJob((Dir() / "job.toml").string());
  return job;
}

void Tune(benchmark::State& state) {
  TuneOptions options;
  options.out = (Dir() / "out").string();
  options.threads = static_cast<int>(state.range(0));
  options.force = true;
  options.html = false;
  options.quiet = true;
  size_t evaluations = 0;
  for (auto _ : state) {
    const TuneResult r = RunTune(Job(), options);
    evaluations += r.evaluations.size();
    benchmark::DoNotOptimize(r.best);
  }
  state.SetItemsProcessed(static_cast<int64_t>(evaluations));  // items/s = evaluations/s
}
BENCHMARK(Tune)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// The peer: the job's own 16 runs (its 8 candidates, both ramps each) as one plain batch, with no
// rounds: what the runs cost when nothing waits for a round to finish.
void PlainBatch(benchmark::State& state) {
  static const std::vector<Suite> suites = [] {
    TuneOptions options;
    options.out = (Dir() / "peer").string();
    options.force = true;
    options.html = false;
    std::vector<Suite> out;
    for (const Evaluation& e : RunTune(Job(), options).evaluations) {
      const ParamOverlay overlay = Job().Overlay(e.x);
      out.push_back(LoadSuite(Job().suites[0], &overlay));
    }
    return out;
  }();
  std::vector<BatchJob> jobs;
  for (const Suite& suite : suites) {
    for (const Scenario& s : suite.scenarios) jobs.push_back({&s, "fuzzy_cmac"});
  }
  GaitLibraryCache libraries;
  for (auto _ : state) {
    RunBatch(jobs, static_cast<int>(state.range(0)), &libraries, [](size_t, RunOutput&&) {});
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * suites.size()));
}
BENCHMARK(PlainBatch)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// The tuner's serial part per candidate: the suite read under the candidate's overlay.
void LoadCandidateSuite(benchmark::State& state) {
  const ParamOverlay overlay = Job().Overlay({0.25, 0.12});
  for (auto _ : state) benchmark::DoNotOptimize(LoadSuite(Job().suites[0], &overlay));
}
BENCHMARK(LoadCandidateSuite)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace rabbit

BENCHMARK_MAIN();
