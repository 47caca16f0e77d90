// CMAC hot paths: one SISO query (direct and hashed storage), one LMS update, one multi-input
// query. Inputs cycle through 1024 seeded random points so that the branch predictor and the
// caches see a realistic spread of addresses.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "rabbit/learn/cmac.h"
#include "rabbit/learn/multi_cmac.h"

namespace rabbit {
namespace {

constexpr int kPoints = 1024;  // a power of two: cycling is a mask

std::vector<double> RandomInputs(int count, double lo, double hi, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  std::vector<double> x(static_cast<size_t>(count));
  for (double& v : x) v = u(rng);
  return x;
}

// The chapter's CMAC (6 layers, 0.25 deg quanta, 1.5 deg fields) over [-1, 1] rad; range(0) is
// the hash table size (0: direct storage, 464 weights).
Cmac ChapterCmac(int hash_table_size) {
  CmacOptions o;
  o.hash_table_size = hash_table_size;
  Cmac cmac(o);
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-0.1, 0.1);
  for (double& w : *cmac.mutable_weights()) w = u(rng);
  return cmac;
}

void BM_CmacQuery(benchmark::State& state) {
  const Cmac cmac = ChapterCmac(static_cast<int>(state.range(0)));
  const std::vector<double> x = RandomInputs(kPoints, -1.1, 1.1, 2);
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(cmac.Query(x[i]));
    i = (i + 1) & (kPoints - 1);
  }
}
BENCHMARK(BM_CmacQuery)->ArgName("table")->Arg(0)->Arg(4096);

void BM_CmacUpdate(benchmark::State& state) {
  Cmac cmac = ChapterCmac(static_cast<int>(state.range(0)));
  const std::vector<double> x = RandomInputs(kPoints, -1.0, 1.0, 3);
  std::vector<double> y(x.size());
  for (size_t k = 0; k < x.size(); ++k) y[k] = std::sin(x[k]);
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(cmac.Update(x[i], y[i], 0.5));
    i = (i + 1) & (kPoints - 1);
  }
}
BENCHMARK(BM_CmacUpdate)->ArgName("table")->Arg(0)->Arg(4096);

// range(0) inputs over [-1, 1] each, the chapter's quanta and fields, 6 layers, 2^16 weights.
void BM_MultiCmacQuery(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  MultiCmacOptions o;
  o.inputs.assign(static_cast<size_t>(n), MultiCmacInput{});
  o.hash_table_size = 1 << 16;
  MultiCmac cmac(o);
  const std::vector<double> w = RandomInputs(o.hash_table_size, -0.1, 0.1, 4);
  *cmac.mutable_weights() = w;
  const std::vector<double> x = RandomInputs(kPoints * n, -1.1, 1.1, 5);
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(cmac.Query(x.data() + i * static_cast<size_t>(n)));
    i = (i + 1) & (kPoints - 1);
  }
}
BENCHMARK(BM_MultiCmacQuery)->ArgName("inputs")->Arg(2)->Arg(3);

}  // namespace
}  // namespace rabbit

BENCHMARK_MAIN();
