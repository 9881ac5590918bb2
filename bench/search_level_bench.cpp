// Cost of the model search's family-wise level (core/sign_flip_max_t.hpp): the max-T law of one
// step from its candidates' gains over runs of 100 ranges. Arguments: runs (a 20,000-range record
// has 200, a day of data at 1 Hz 864), candidates.
#include <benchmark/benchmark.h>

#include <random>

#include "core/sign_flip_max_t.hpp"

namespace {

void BM_SignFlipMaxT(benchmark::State& state) {
  const auto runs = static_cast<Eigen::Index>(state.range(0));
  const auto candidates = static_cast<Eigen::Index>(state.range(1));
  std::mt19937_64 rng(1);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd gains(runs, candidates);
  for (Eigen::Index j = 0; j < gains.size(); ++j) gains.data()[j] = normal(rng);
  for (auto _ : state) {
    const tofcomp::core::SignFlipMaxT law(gains);
    benchmark::DoNotOptimize(law.critical_t(0.05));
  }
}

}  // namespace

BENCHMARK(BM_SignFlipMaxT)->ArgsProduct({{200, 864}, {36, 44}})->Unit(benchmark::kMillisecond);
