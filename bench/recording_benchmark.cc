// What recording costs: one CSV number (FormatCsvNumber, the shortest round-trip form), one
// trajectory row (41 numbers), and 30 s of flat walking (the paper suite's "flat", Fuzzy-CMAC
// walker) recorded every n-th control period and written as a run folder (meta, trajectory,
// steps, tracking, terrain, ground), against the same walk recording nothing and writing nothing.
// Run with --benchmark_enable_random_interleaving=true: the walks alternate.
#include <benchmark/benchmark.h>
#include <stdlib.h>

#include <filesystem>
#include <random>
#include <sstream>

#include "rabbit/io/csv.h"
#include "rabbit/scenario/run_files.h"
#include "rabbit/scenario/run.h"
#include "rabbit/scenario/suite.h"
#include "rabbit/scenario/trajectory_csv.h"

namespace rabbit {
namespace {

const Suite& Paper() {
  static const Suite suite = LoadSuite(std::string(RABBIT_SOURCE_DIR) + "/scenarios/paper.toml");
  return suite;
}

const Scenario& Flat() {
  for (const Scenario& s : Paper().scenarios) {
    if (s.name == "flat") return s;
  }
  throw std::runtime_error("no scenario flat");
}

void BM_FormatCsvNumber(benchmark::State& state) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> uniform(-3.0, 3.0);
  std::vector<double> values(4096);
  for (double& v : values) v = uniform(rng);
  size_t i = 0;
  std::string out;
  out.reserve(64);
  for (auto _ : state) {
    out.clear();
    AppendCsvNumber(values[i++ & 4095], &out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_FormatCsvNumber);

// Trajectory rows of a real walk (1 s of samples), written to a string stream; per row.
void BM_TrajectoryCsvRows(benchmark::State& state) {
  Scenario s = Flat();
  s.options.duration = 2.0;
  s.options.record_every = 1;
  const std::shared_ptr<const GaitLibrary> library = LoadGaitLibrary(s.pattern);
  const RunOutput run = RunScenario(s, "fuzzy_cmac", library.get());
  for (auto _ : state) {
    std::ostringstream out;
    WriteTrajectoryCsv(run.sim, out);
    benchmark::DoNotOptimize(out.str().size());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long>(run.sim.samples.size()));
  state.counters["s_per_number"] = benchmark::Counter(
      static_cast<double>(state.iterations()) * static_cast<double>(run.sim.samples.size()) * 41.0,
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_TrajectoryCsvRows)->Unit(benchmark::kMicrosecond);

// Arg: record_every (0: nothing recorded, no files written).
void BM_WalkFlatRecorded(benchmark::State& state) {
  Scenario s = Flat();
  s.options.record_every = static_cast<int>(state.range(0));
  const std::shared_ptr<const GaitLibrary> library = LoadGaitLibrary(s.pattern);
  namespace fs = std::filesystem;
  std::string dir = (fs::temp_directory_path() / "rabbit-recording-XXXXXX").string();
  if (::mkdtemp(dir.data()) == nullptr) {
    state.SkipWithError("mkdtemp failed");
    return;
  }
  for (auto _ : state) {
    const RunOutput run = RunScenario(s, "fuzzy_cmac", library.get());
    if (state.range(0) > 0) WriteRunFiles(s, run, dir);
    benchmark::DoNotOptimize(run.metrics.distance);
  }
  fs::remove_all(dir);
}
BENCHMARK(BM_WalkFlatRecorded)->Arg(0)->Arg(10)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace rabbit

BENCHMARK_MAIN();
