// The Fuzzy-CMAC gait pattern's query (the per-period hot path) and a full training, against
// fuzzylite's inference of the same fuzzy system, on the shipped gaits, networks and FLL.
//   FuzzyCmac/Query          the four references at e with the FIS weights held (every period);
//   FuzzyCmac/ContextAndQuery the FIS at [V_M, d_obs] and then the query (once per step);
//   Fuzzylite/Process        fuzzylite's engine->process() of gaits/gait_pattern.fll;
//   Train/Ceres, Train/Lms   fitting the 20 CMACs of the five reference gaits.
#include <benchmark/benchmark.h>
#include <fl/Headers.h>

#include <random>

#include "cmac_fit.h"
#include "rabbit/gait/gait_database.h"
#include "rabbit/learn/cmac_training.h"
#include "rabbit/learn/fll.h"
#include "rabbit/learn/gait_pattern.h"

#ifndef RABBIT_SOURCE_DIR
#define RABBIT_SOURCE_DIR "."
#endif

namespace rabbit {
namespace {

const std::string kRoot = RABBIT_SOURCE_DIR;

struct Inputs {
  std::vector<double> v, d, e;
  Inputs() {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> uv(0.35, 0.85), ud(0.0, 1.0), ue(-0.1, 0.5);
    for (int i = 0; i < 1024; ++i) {
      v.push_back(uv(rng));
      d.push_back(ud(rng));
      e.push_back(ue(rng));
    }
  }
};

void BM_FuzzyCmacQuery(benchmark::State& state) {
  FuzzyCmac pattern = LoadGaitPattern(kRoot + "/gaits/gait_pattern.fll", kRoot + "/gaits/networks");
  const Inputs in;
  pattern.SetContext(0.55, 0.3);  // several rules and gaits active
  size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(pattern.Query(in.e[i++ & 1023]));
}
BENCHMARK(BM_FuzzyCmacQuery);

void BM_FuzzyCmacContextAndQuery(benchmark::State& state) {
  FuzzyCmac pattern = LoadGaitPattern(kRoot + "/gaits/gait_pattern.fll", kRoot + "/gaits/networks");
  const Inputs in;
  size_t i = 0;
  for (auto _ : state) {
    const size_t k = i++ & 1023;
    pattern.SetContext(in.v[k], in.d[k]);
    benchmark::DoNotOptimize(pattern.Query(in.e[k]));
  }
}
BENCHMARK(BM_FuzzyCmacContextAndQuery);

void BM_FuzzyliteProcess(benchmark::State& state) {
  fl::FllImporter importer;
  std::unique_ptr<fl::Engine> engine(importer.fromFile(kRoot + "/gaits/gait_pattern.fll"));
  fl::InputVariable* v = engine->getInputVariable("V_M");
  fl::InputVariable* d = engine->getInputVariable("d_obs");
  fl::OutputVariable* out = engine->getOutputVariable(0);
  const Inputs in;
  size_t i = 0;
  for (auto _ : state) {
    const size_t k = i++ & 1023;
    v->setValue(in.v[k]);
    d->setValue(in.d[k]);
    engine->process();
    benchmark::DoNotOptimize(out->getValue());
  }
}
BENCHMARK(BM_FuzzyliteProcess);

void Train(benchmark::State& state, bool ceres) {
  const std::vector<GaitIndexEntry> index = ReadGaitIndex(kRoot + "/gaits/reference/index.csv");
  std::vector<GaitRecord> gaits;
  for (const GaitIndexEntry& e : index)
    gaits.push_back(ReadGaitFile(kRoot + "/gaits/reference/" + e.file));
  CmacOptions options;
  options.x_min = -0.3;
  options.x_max = 0.7;
  for (auto _ : state) {
    for (const GaitRecord& g : gaits) {
      std::vector<double> x;
      std::array<std::vector<double>, kGaitOutputs> y;
      SplitSwing(g.swing, &x, &y);
      for (int o = 0; o < kGaitOutputs; ++o) {
        Cmac cmac(options);
        if (ceres) {
          FitCmacCeres(x, y[o], CmacFitOptions{}, &cmac);
        } else {
          TrainCmacLms(x, y[o], LmsOptions{}, &cmac);
        }
        benchmark::DoNotOptimize(cmac.weights().data());
      }
    }
  }
}
void BM_TrainCeres(benchmark::State& state) { Train(state, true); }
void BM_TrainLms(benchmark::State& state) { Train(state, false); }
BENCHMARK(BM_TrainCeres)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TrainLms)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace rabbit

BENCHMARK_MAIN();
