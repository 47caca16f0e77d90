// The gait pattern's inference (gaits/gait_pattern.fll, 2 inputs x 5 sets, 25 rules): our compiled
// evaluator (TsFis::Evaluate, result reused) against fuzzylite 6's engine->process() on the same
// system read by fuzzylite's own importer. Both cycle through the same fixed set of 1024 seeded
// random inputs (V_M over [0.3, 0.9] m/s, d_obs over [0, 0.6] m, so 1 to 4 rules fire), and each
// checks that it agrees with the other on those inputs before timing. Unless told otherwise the
// program runs 5 repetitions with random interleaving, so both sides see the same machine
// conditions; pass --benchmark_repetitions=1 for a quick run.
#include <benchmark/benchmark.h>
#include <fl/Headers.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "rabbit/learn/fll.h"
#include "rabbit/learn/ts_fis.h"

#ifndef RABBIT_SOURCE_DIR
#define RABBIT_SOURCE_DIR "."
#endif

namespace rabbit {
namespace {

const std::string kFll = std::string(RABBIT_SOURCE_DIR) + "/gaits/gait_pattern.fll";
constexpr std::size_t kInputs = 1024;  // a power of two

const std::vector<std::array<double, 2>>& Inputs() {
  static const std::vector<std::array<double, 2>> inputs = [] {
    std::mt19937_64 rng(20240601);
    std::uniform_real_distribution<double> v_m(0.3, 0.9), d_obs(0.0, 0.6);
    std::vector<std::array<double, 2>> result(kInputs);
    for (auto& x : result) x = {v_m(rng), d_obs(rng)};
    return result;
  }();
  return inputs;
}

// Both evaluators over the whole input set; the benchmarks refuse to run if they disagree.
bool Agree() {
  const TsFis fis = LoadFll(kFll);
  std::unique_ptr<fl::Engine> engine(fl::FllImporter().fromFile(kFll));
  TsFis::Result r;
  for (const auto& x : Inputs()) {
    fis.Evaluate({x[0], x[1]}, &r);
    engine->getInputVariable(0)->setValue(x[0]);
    engine->getInputVariable(1)->setValue(x[1]);
    engine->process();
    if (!(std::abs(r.output - engine->getOutputVariable(0)->getValue()) <= 1e-12)) return false;
  }
  return true;
}

void BM_GaitPattern_Rabbit(benchmark::State& state) {
  if (!Agree()) {
    state.SkipWithError("our evaluator and fuzzylite disagree");
    return;
  }
  const TsFis fis = LoadFll(kFll);
  const auto& inputs = Inputs();
  TsFis::Result r;
  std::vector<double> x(2);
  fis.Evaluate(x, &r);  // sizes the result once
  std::size_t i = 0;
  double sum = 0;
  for (auto _ : state) {
    const auto& in = inputs[i++ & (kInputs - 1)];
    x[0] = in[0];
    x[1] = in[1];
    fis.Evaluate(x, &r);
    benchmark::DoNotOptimize(r.output);
    sum += r.output;
  }
  benchmark::DoNotOptimize(sum);
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()));
}

void BM_GaitPattern_Fuzzylite(benchmark::State& state) {
  if (!Agree()) {
    state.SkipWithError("our evaluator and fuzzylite disagree");
    return;
  }
  std::unique_ptr<fl::Engine> engine(fl::FllImporter().fromFile(kFll));
  fl::InputVariable* v_m = engine->getInputVariable(0);
  fl::InputVariable* d_obs = engine->getInputVariable(1);
  const fl::OutputVariable* gait = engine->getOutputVariable(0);
  const auto& inputs = Inputs();
  std::size_t i = 0;
  double sum = 0;
  for (auto _ : state) {
    const auto& in = inputs[i++ & (kInputs - 1)];
    v_m->setValue(in[0]);
    d_obs->setValue(in[1]);
    engine->process();
    double output = gait->getValue();
    benchmark::DoNotOptimize(output);
    sum += output;
  }
  benchmark::DoNotOptimize(sum);
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()));
}

BENCHMARK(BM_GaitPattern_Rabbit);
BENCHMARK(BM_GaitPattern_Fuzzylite);

}  // namespace
}  // namespace rabbit

// Defaults to 5 interleaved repetitions; any flag given on the command line overrides them.
int main(int argc, char** argv) {
  std::vector<char*> args{argv[0]};
  std::string repetitions = "--benchmark_repetitions=5";
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
