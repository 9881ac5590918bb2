// The residual tests of `tofcomp diagnose` (core/residual_diagnosis.hpp) on a day of ranges
// (86,400: one a second), judged by their textbook laws (0 draws) or by the trained model's draws,
// one thread. Ranges of Eq. 8 with two lasing modes and a bias that moves the rounding's lattice
// with a slow temperature cycle.
//   build/bench/residual_diagnosis_bench
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include "core/residual_diagnosis.hpp"

namespace {

constexpr Eigen::Index kDayOfRanges = 86400;

struct DayOfRanges {
  tofcomp::core::DiagnosisInput input;
  tofcomp::core::MixtureParameters mixture;
};

DayOfRanges day_of_ranges() {
  DayOfRanges day;
  day.mixture.mean = Eigen::Vector2d(-1.5, 2.0);
  day.mixture.variance = Eigen::Vector2d(1.0, 1.44);
  day.mixture.weight = Eigen::Vector2d(0.55, 0.45);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  auto& in = day.input;
  in.time_s.resize(kDayOfRanges);
  in.junction_c.resize(kDayOfRanges);
  in.junction_rate_c_per_s.resize(kDayOfRanges);
  in.time_since_power_on_s.resize(kDayOfRanges);
  in.residual.resize(kDayOfRanges);
  in.predicted_mm.resize(kDayOfRanges);
  for (Eigen::Index k = 0; k < kDayOfRanges; ++k) {
    const double t = static_cast<double>(k);
    in.time_s[k] = t;
    in.junction_c[k] = 30.0 + 4.0 * std::sin(2.0 * M_PI * t / 7200.0);
    in.junction_rate_c_per_s[k] = 4.0 * 2.0 * M_PI / 7200.0 * std::cos(2.0 * M_PI * t / 7200.0);
    in.time_since_power_on_s[k] = std::fmod(t, 7200.0);
    in.predicted_mm[k] = 3000.0 + 0.8 * (in.junction_c[k] - 30.0);
    const int mode = uniform(rng) < day.mixture.weight[0] ? 0 : 1;
    const double w = day.mixture.mean[mode] + std::sqrt(day.mixture.variance[mode]) * normal(rng);
    in.residual[k] = std::round(in.predicted_mm[k] + w) - in.predicted_mm[k];
  }
  return day;
}

void BM_ResidualDiagnosis(benchmark::State& state) {
  static const DayOfRanges day = day_of_ranges();
  tofcomp::core::DiagnosisOptions options;
  options.resolution_mm = 1.0;
  options.null_draws = static_cast<int>(state.range(0));
  for (auto _ : state) {
    benchmark::DoNotOptimize(tofcomp::core::diagnose_residuals(day.input, day.mixture, options));
  }
}

}  // namespace

BENCHMARK(BM_ResidualDiagnosis)->Arg(0)->Arg(64)->Unit(benchmark::kMillisecond)->MinTime(1.0);
