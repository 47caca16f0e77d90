// Tuning throughput (issue 6): evaluations per second of a tuning job on 1 and 2 threads, against
// its peer, the same runs as a plain batch (RunBatch over the suites loaded once): the tuner's own
// cost per evaluation (loading the suites under the candidate's overlay, the rounds, the log) is
// the difference. The job: 2 searches of CRS2 over the velocity gains, 12 s of each ramp of
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

// The peer: the same 16 runs (8 candidates' worth of both ramps at the initial gains) as a batch.
void PlainBatch(benchmark::State& state) {
  static const Suite suite = LoadSuite(Job().suites[0], &Job().base);
  std::vector<BatchJob> jobs;
  for (int c = 0; c < 8; ++c) {
    for (const Scenario& s : suite.scenarios) jobs.push_back({&s, "fuzzy_cmac"});
  }
  GaitLibraryCache libraries;
  size_t runs = 0;
  for (auto _ : state) {
    RunBatch(jobs, static_cast<int>(state.range(0)), &libraries,
             [&runs](size_t, RunOutput&&) { ++runs; });
  }
  state.SetItemsProcessed(static_cast<int64_t>(runs / 2));  // per 2 runs: one evaluation's worth
}
BENCHMARK(PlainBatch)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace rabbit

BENCHMARK_MAIN();
