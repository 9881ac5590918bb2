// Cost of EM training (§5) and testing (§6) against the number of samples K and basis
// columns p. The bases are polynomial(1) + fourier(n), p = 1 + 2n, on a temperature ramp over
// one Fourier period, so every p up to the paper's Fourier order 180 (p = 361) is well posed.
// Training runs a fixed number of plain EM iterations (no SQUAREM: every iteration the same
// work) so that times compare across K and p.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include "core/basis.hpp"
#include "core/column_products.hpp"
#include "core/em_test.hpp"
#include "core/em_train.hpp"
#include "core/extended_em.hpp"
#include "core/vector_math.hpp"

namespace {

using tofcomp::core::Basis;
using tofcomp::core::BasisKind;
using tofcomp::core::BasisTerm;
using tofcomp::core::PolynomialForm;
using tofcomp::core::TemperatureScaling;

constexpr double kLowC = 24.8;
constexpr double kHighC = 28.8;
constexpr int kTrainIterations = 10;

Basis bench_basis(int columns) {
  const int harmonics = (columns - 1) / 2;
  return Basis(
      {BasisTerm{BasisKind::Polynomial, 1, PolynomialForm::Legendre, 0.0},
       BasisTerm{BasisKind::Fourier, harmonics, PolynomialForm::Legendre, 1.0 / (kHighC - kLowC)}},
      TemperatureScaling{0.5 * (kLowC + kHighC), 0.5 * (kHighC - kLowC)});
}

struct BenchData {
  Eigen::VectorXd temperature;
  Eigen::VectorXd y;
};

// Two modes 5 units apart on a linear bias, seeded.
BenchData bench_data(Eigen::Index k) {
  std::mt19937_64 rng(42);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::bernoulli_distribution mode(0.4);
  BenchData d{Eigen::VectorXd::LinSpaced(k, kLowC, kHighC - 1e-6), Eigen::VectorXd(k)};
  for (Eigen::Index i = 0; i < k; ++i) {
    d.y[i] = -2.0 * (d.temperature[i] - kLowC) + (mode(rng) ? 3.0 : -2.0) + noise(rng);
  }
  return d;
}

// Time per EM training iteration: a fixed run of kTrainIterations iterations plus the
// least-squares start; the counter reports the time divided by kTrainIterations + 1.
void BM_EmTrainIteration(benchmark::State& state) {
  const Eigen::Index k = state.range(0);
  const int columns = static_cast<int>(state.range(1));
  const BenchData data = bench_data(k);
  const Eigen::MatrixXd h = bench_basis(columns).design_matrix(data.temperature);
  tofcomp::core::EmTrainOptions options;
  options.max_iterations = kTrainIterations;
  options.weight_tolerance = 1e-300;
  options.log_likelihood_tolerance = 0.0;
  options.record_trace = false;
  options.acceleration = tofcomp::core::EmAcceleration::None;
  for (auto _ : state) {
    auto fit = tofcomp::core::train_em(h, data.y, options);
    benchmark::DoNotOptimize(fit.theta.data());
  }
  state.counters["K"] = static_cast<double>(k);
  state.counters["p"] = columns;
  state.counters["s_per_iteration"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * (kTrainIterations + 1),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// The same iteration on each path of core/vector_math.hpp and core/column_products.hpp
// (argument 2: 0 portable, 1 AVX2 + FMA; skipped where the CPU lacks it), side by side.
void BM_EmTrainIterationOnPath(benchmark::State& state) {
  const auto path = static_cast<tofcomp::core::VectorMathPath>(state.range(2));
  if (!tofcomp::core::vector_math_path_available(path)) {
    state.SkipWithError("this CPU cannot run the path");
    return;
  }
  tofcomp::core::pin_vector_math_path(path);
  BM_EmTrainIteration(state);
  tofcomp::core::pin_vector_math_path(std::nullopt);
  state.SetLabel(tofcomp::core::vector_math_path_name(path));
}

// The exact M-step's products over one chunk of 512 ranges (core/mixture_sweep.cpp): the lower
// Gram matrix of p columns, their products with M = 2 weight columns and the residual e − Hθ,
// per path (argument 1).
void BM_ColumnProducts(benchmark::State& state) {
  constexpr Eigen::Index kRanges = 512;
  constexpr Eigen::Index kModes = 2;
  const Eigen::Index p = state.range(0);
  const auto path = static_cast<tofcomp::core::VectorMathPath>(state.range(1));
  if (!tofcomp::core::vector_math_path_available(path)) {
    state.SkipWithError("this CPU cannot run the path");
    return;
  }
  // Columns kLeading doubles apart, as the sweep lays its chunk out (core/mixture_sweep.cpp).
  constexpr Eigen::Index kLeading = kRanges + 8;
  const Eigen::MatrixXd x_storage = Eigen::MatrixXd::Random(kLeading, p);
  const Eigen::MatrixXd w_storage = Eigen::MatrixXd::Random(kLeading, kModes);
  const auto x = x_storage.topRows(kRanges);
  const auto w = w_storage.topRows(kRanges);
  const Eigen::VectorXd theta = Eigen::VectorXd::Random(p);
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(p, p), sums = Eigen::MatrixXd::Zero(p, kModes);
  Eigen::VectorXd e = Eigen::VectorXd::Random(kRanges);
  for (auto _ : state) {
    tofcomp::core::add_lower_gram(x, gram, path);
    tofcomp::core::add_cross_products(x, w, sums, path);
    tofcomp::core::subtract_product(x, theta, e, path);
    benchmark::DoNotOptimize(gram.data());
    benchmark::DoNotOptimize(sums.data());
    benchmark::DoNotOptimize(e.data());
  }
  state.SetLabel(tofcomp::core::vector_math_path_name(path));
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * kRanges);
}

// Time of EM testing of one window of K samples (the bias Hθ̂ is precomputed, as in use).
void BM_EmTest(benchmark::State& state) {
  const Eigen::Index k = state.range(0);
  const BenchData data = bench_data(k);
  const Eigen::VectorXd bias = -2.0 * (data.temperature.array() - kLowC);
  tofcomp::core::MixtureParameters mixture;
  mixture.mean = Eigen::Vector2d(-2.0, 3.0);
  mixture.variance = Eigen::Vector2d(1.0, 1.0);
  mixture.weight = Eigen::Vector2d(0.6, 0.4);
  tofcomp::core::EmTestOptions options;
  int iterations = 0;
  for (auto _ : state) {
    auto fit = tofcomp::core::test_em(data.y, bias, mixture, options);
    iterations = fit.iterations;
    benchmark::DoNotOptimize(fit.distance);
  }
  state.counters["K"] = static_cast<double>(k);
  state.counters["em_iterations"] = iterations;
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * k);
}

// Time per iteration of the extended EM's generic step (core/extended_em.hpp) on K ranges,
// p = 4 shared columns (a cubic), four modes, in the shapes the model search fits most:
// argument 1 is 0 for one mode's offset on a covariate column, 1 for the spreads in 8 bins,
// 2 for the weights in 8 bins. Plain EM, a fixed number of iterations.
void BM_ExtendedEmIteration(benchmark::State& state) {
  constexpr int kModes = 4;
  constexpr int kBins = 8;
  const Eigen::Index k = state.range(0);
  const int shape = static_cast<int>(state.range(1));
  const BenchData data = bench_data(k);
  tofcomp::core::ExtendedDesign design;
  design.shared = bench_basis(3).design_matrix(data.temperature);
  design.shared.conservativeResize(Eigen::NoChange, 4);
  design.shared.col(3) = design.shared.col(1).array().cube().matrix();
  design.mode_columns.assign(kModes, Eigen::MatrixXd());
  design.state = Eigen::VectorXi::Zero(k);
  tofcomp::core::ExtendedParameters start;
  start.theta = Eigen::VectorXd::Zero(4);
  start.mode_coefficients.assign(kModes, Eigen::VectorXd());
  start.model.modes.mean = Eigen::Vector4d(-2.5, -1.5, 2.5, 3.5);
  start.model.modes.variance = Eigen::Vector4d::Ones();
  start.model.modes.weight = Eigen::Vector4d::Constant(0.25);
  const Eigen::VectorXd ramp = Eigen::VectorXd::LinSpaced(k, -1.0, 1.0);
  if (shape == 0) {
    design.mode_columns[1] = ramp;
    start.mode_coefficients[1] = Eigen::VectorXd::Zero(1);
  } else {
    tofcomp::core::NoiseBins bins;
    bins.term.parameter =
        shape == 1 ? tofcomp::core::Parameter::Spread : tofcomp::core::Parameter::Weights;
    bins.term.covariate = tofcomp::core::Covariate::Time;
    bins.term.form = tofcomp::core::Form::Bins;
    bins.term.knots = Eigen::VectorXd::LinSpaced(kBins - 1, -0.75, 0.75);
    bins.table = Eigen::MatrixXd::Constant(kBins, kModes, shape == 1 ? 1.0 : 0.25);
    for (Eigen::Index i = 0; i < k; ++i) {
      design.state[i] = static_cast<int>(std::min<Eigen::Index>(kBins - 1, i * kBins / k));
    }
    if (shape == 1) {
      start.model.variance_bins = bins;
    } else {
      start.model.weight_bins = bins;
    }
  }
  tofcomp::core::ExtendedEmOptions options;
  options.max_iterations = kTrainIterations;
  options.log_likelihood_tolerance = 0.0;
  options.acceleration = tofcomp::core::EmAcceleration::None;
  for (auto _ : state) {
    auto fit = tofcomp::core::train_extended_em(design, data.y, start, options);
    benchmark::DoNotOptimize(fit.fit.theta.data());
  }
  state.counters["K"] = static_cast<double>(k);
  state.counters["ns_per_range_iteration"] = benchmark::Counter(
      static_cast<double>(state.iterations()) * kTrainIterations * static_cast<double>(k),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert,
      benchmark::Counter::OneK::kIs1000);
  state.SetLabel(shape == 0 ? "mode offset column" : shape == 1 ? "spread bins" : "weight bins");
}

void train_grid(benchmark::internal::Benchmark* b) {
  for (const int columns : {3, 17, 61, 361}) {
    for (const int64_t k : {1000, 3000, 10000, 30000, 100000}) {
      if (k > columns * 2) b->Args({k, columns});
    }
  }
}

}  // namespace

BENCHMARK(BM_EmTrainIteration)->Apply(train_grid)->Unit(benchmark::kMillisecond)->MinTime(0.2);
BENCHMARK(BM_EmTrainIterationOnPath)
    ->ArgsProduct({{10000, 100000}, {3, 17}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(0.2);
BENCHMARK(BM_ExtendedEmIteration)
    ->ArgsProduct({{86400}, {0, 1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(0.5);
BENCHMARK(BM_ColumnProducts)->ArgsProduct({{3, 17, 61}, {0, 1}})->MinTime(0.2);
BENCHMARK(BM_EmTest)
    ->RangeMultiplier(10)
    ->Range(200, 200000)
    ->Arg(400)
    ->Arg(800)
    ->Unit(benchmark::kMicrosecond);
