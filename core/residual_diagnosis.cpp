#include "core/residual_diagnosis.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "core/em_train.hpp"
#include "core/error.hpp"
#include "core/validation.hpp"
#include "core/warm_up.hpp"

namespace tofcomp::core {
namespace {

constexpr Eigen::Index kMinRanges = 100;
constexpr int kTemperatureBins = 4;

Finding make(EffectKind kind, const char* test, const char* covariate, TestResult result) {
  return Finding{kind, test, covariate, result, false};
}

// The quartile of each temperature (0..3) by rank.
Eigen::VectorXi quartiles(const Eigen::VectorXd& t) {
  std::vector<Eigen::Index> order(static_cast<std::size_t>(t.size()));
  for (Eigen::Index i = 0; i < t.size(); ++i) order[static_cast<std::size_t>(i)] = i;
  std::sort(order.begin(), order.end(), [&](auto a, auto b) { return t[a] < t[b]; });
  Eigen::VectorXi bin(t.size());
  for (std::size_t rank = 0; rank < order.size(); ++rank) {
    bin[order[rank]] = static_cast<int>(rank * kTemperatureBins / order.size());
  }
  return bin;
}

// Ranks 0..n−1 (ties broken by position: the values here are continuous).
Eigen::VectorXd ranks(const Eigen::VectorXd& v) {
  std::vector<Eigen::Index> order(static_cast<std::size_t>(v.size()));
  for (Eigen::Index i = 0; i < v.size(); ++i) order[static_cast<std::size_t>(i)] = i;
  std::stable_sort(order.begin(), order.end(), [&](auto a, auto b) { return v[a] < v[b]; });
  Eigen::VectorXd r(v.size());
  for (std::size_t i = 0; i < order.size(); ++i) r[order[i]] = static_cast<double>(i);
  return r;
}

// Each residual less the nearest mode's offset, in units of a scale outliers do not inflate:
// 1.4826 × the median absolute value of those differences (σ for Gaussian modes). The nearest
// offset, not the most probable mode: an EM that grew one broad mode around the outliers would
// otherwise measure them against that mode's own breadth.
Eigen::VectorXd nearest_mode_deviation(const Eigen::VectorXd& residual,
                                       const MixtureParameters& mixture) {
  Eigen::VectorXd deviation(residual.size());
  for (Eigen::Index k = 0; k < residual.size(); ++k) {
    deviation[k] = (mixture.mean.array() - residual[k]).abs().minCoeff();
  }
  std::vector<double> sorted(deviation.data(), deviation.data() + deviation.size());
  auto middle = sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2);
  std::nth_element(sorted.begin(), middle, sorted.end());
  return deviation / std::max(1.4826 * *middle, 1e-12);
}

// The extra-mode test's EM fits: their cap, and their stopping rule. The split likelihood ratio
// reads only the halves' log-likelihoods, so EM stops when the log-likelihood has settled, not on
// the paper's rule on the weights: on a flat ridge (two near-equal modes, which a structure search
// that counted M modes often keeps) the weights drift for hundreds of iterations while the
// likelihood creeps by 1e-5 nats an iteration (on a day record of 86,400 ranges all four fits ran
// to the cap of 500 that way, a fifth of diagnose's EM work). The likelihood's rule: under 1e-9
// nats per range an iteration (4e-5 nats on a half of that record: 78-199 iterations there),
// which leaves the null's likelihood 0.06-0.16 nats below where the cap of 500 left it (the
// crawl had not ended there either), against the test's threshold of log(9 / 0.05) = 5.2 nats.
// The weights' rule is off (kWeightRuleOff).
constexpr int kExtraModeMaxIterations = 500;
constexpr double kExtraModeLogLikelihoodTolerance = 1e-9;

// The (M)-mode and (M+1)-mode mixtures of one half, by the paper's EM with no bias columns;
// no value when EM cannot keep that many modes populated.
// start: the mixture EM starts from (the quantile start when none).
std::optional<MixtureParameters> fit_modes(const Eigen::VectorXd& residual, int modes,
                                           const MixtureParameters* start = nullptr) {
  EmTrainOptions options;
  options.modes = modes;
  options.record_trace = false;
  options.max_iterations = kExtraModeMaxIterations;
  options.weight_tolerance = kWeightRuleOff;
  options.log_likelihood_tolerance = kExtraModeLogLikelihoodTolerance;
  if (start) options.start = EmStartingPoint{Eigen::VectorXd(0), *start};
  try {
    return train_em(Eigen::MatrixXd(residual.size(), 0), residual, options).mixture;
  } catch (const NumericalError&) {
    return std::nullopt;
  }
}

// One more mode: the split likelihood ratio, fitted on one half and evaluated on the other,
// both ways, T = (T_ab + T_ba) / 2. The null's M modes on a half start from the trained mixture
// (the maximum on all the ranges, near each half's); the alternative's M + 1 from the quantiles.
TestResult extra_mode_test(const Eigen::VectorXd& residual, const MixtureParameters& trained) {
  const int modes = trained.modes();
  const Eigen::Index half = residual.size() / 2;
  const Eigen::VectorXd first = residual.head(half);
  const Eigen::VectorXd second = residual.tail(residual.size() - half);
  const auto log_t = [&](const Eigen::VectorXd& fit_on, const Eigen::VectorXd& test_on) {
    const auto alternative = fit_modes(fit_on, modes + 1);
    const auto null = fit_modes(test_on, modes, &trained);
    if (!alternative || !null) return -std::numeric_limits<double>::infinity();
    return mixture_log_likelihood(test_on, *alternative) - mixture_log_likelihood(test_on, *null);
  };
  const double a = log_t(first, second);
  const double b = log_t(second, first);
  const double top = std::max(a, b);
  const double log_mean =
      std::isfinite(top) ? top + std::log(0.5 * (std::exp(a - top) + std::exp(b - top))) : top;
  return split_likelihood_ratio_test(std::isfinite(log_mean) ? log_mean : 0.0);
}

// Serial dependence is a symptom of any structure in time; a named effect ranks before it.
bool generic(EffectKind kind) {
  return kind == EffectKind::SerialDependence;
}

}  // namespace

const char* effect_name(EffectKind kind) {
  switch (kind) {
    case EffectKind::ModePersistence:
      return "mode persistence";
    case EffectKind::TemperatureDependentWeights:
      return "temperature-dependent mode weights";
    case EffectKind::TemperatureDependentSpread:
      return "temperature-dependent spread";
    case EffectKind::Outliers:
      return "outliers";
    case EffectKind::HeatingHysteresis:
      return "heating hysteresis";
    case EffectKind::TimeDrift:
      return "time drift";
    case EffectKind::WarmUp:
      return "warm-up after power-on";
    case EffectKind::ExtraMode:
      return "one more lasing mode";
    case EffectKind::SerialDependence:
      return "serial dependence";
  }
  return "unknown";
}

Diagnosis diagnose_residuals(const DiagnosisInput& in, const MixtureParameters& mixture,
                             const DiagnosisOptions& options) {
  const Eigen::Index n = in.residual.size();
  require_same_length(in.time_s.size(), "time", n, "residual");
  require_same_length(in.junction_c.size(), "junction temperature", n, "residual");
  require_same_length(in.junction_rate_c_per_s.size(), "junction rate", n, "residual");
  require_same_length(in.time_since_power_on_s.size(), "time since power-on", n, "residual");
  require_finite(in.residual, "residual");
  require_finite(in.junction_c, "junction temperature");
  require_finite(in.junction_rate_c_per_s, "junction rate");
  require_finite(in.time_since_power_on_s, "time since power-on");
  mixture.validate();
  if (n < kMinRanges) throw InvalidInput("the diagnosis needs at least 100 ranges");

  Diagnosis d;
  Eigen::MatrixXd r;
  mixture_e_step(in.residual, mixture, r);
  d.mode.resize(n);
  d.compensated.resize(n);
  d.standardized.resize(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    Eigen::Index best = 0;
    r.row(k).maxCoeff(&best);
    d.mode[k] = static_cast<int>(best);
    d.compensated[k] = in.residual[k] - mixture.mean[best];
    d.standardized[k] = d.compensated[k] / std::sqrt(mixture.variance[best]);
  }

  if (mixture.modes() >= 2) {
    const Eigen::VectorXi first = (d.mode.array() == 0).cast<int>();
    if (first.sum() >= 2 && n - first.sum() >= 2) {
      d.findings.push_back(make(EffectKind::ModePersistence, "runs test",
                                "order of the modes in time", runs_test(first)));
      d.findings.back().result.z = -d.findings.back().result.statistic;  // fewer runs
    }
    const Eigen::VectorXi bin = quartiles(in.junction_c);
    Eigen::MatrixXd table = Eigen::MatrixXd::Zero(kTemperatureBins, mixture.modes());
    for (Eigen::Index k = 0; k < n; ++k) table(bin[k], d.mode[k]) += 1.0;
    d.findings.push_back(make(EffectKind::TemperatureDependentWeights, "chi-square independence",
                              "junction temperature quartile", chi_square_independence(table)));
  }
  // Rank correlation, so that a few large residuals do not pass for a change of spread.
  d.findings.push_back(make(
      EffectKind::TemperatureDependentSpread, "Spearman correlation", "junction temperature vs |z|",
      correlation_test(ranks(in.junction_c), ranks(d.standardized.cwiseAbs()))));
  const Eigen::VectorXd deviation = nearest_mode_deviation(in.residual, mixture);
  const double beyond = static_cast<double>((deviation.array() > options.tail_z).count());
  d.findings.push_back(
      make(EffectKind::Outliers, "tail excess", "|e - nearest mu| > 8 robust sigma",
           tail_excess_test(beyond, static_cast<double>(n), two_sided_normal_p(options.tail_z))));
  d.findings.push_back(make(EffectKind::ExtraMode, "split likelihood ratio",
                            "M + 1 modes against M",
                            extra_mode_test(in.residual, mixture)));
  d.findings.push_back(make(EffectKind::HeatingHysteresis, "correlation", "junction heating rate",
                            correlation_test(in.junction_rate_c_per_s, d.compensated)));
  d.findings.push_back(make(EffectKind::TimeDrift, "correlation", "time",
                            correlation_test(in.time_s, d.compensated)));
  d.findings.push_back(
      make(EffectKind::WarmUp, "max correlation, 7 taus", "exp(-time since power-on / tau)",
           best_correlation_test(warm_up_covariates(in.time_since_power_on_s), d.compensated)));
  d.findings.push_back(make(
      EffectKind::SerialDependence, "Ljung-Box", "lags 1..20",
      ljung_box(d.compensated, std::min<int>(options.ljung_box_lags, static_cast<int>(n / 4)))));

  const double level = options.alpha / static_cast<double>(d.findings.size());
  for (auto& f : d.findings) {
    f.significant = f.result.p_value < level && f.result.z > 0.0;
  }
  std::stable_sort(d.findings.begin(), d.findings.end(), [](const Finding& a, const Finding& b) {
    if (a.significant != b.significant) return a.significant;
    if (a.significant && generic(a.kind) != generic(b.kind)) return !generic(a.kind);
    return a.result.z > b.result.z;
  });
  return d;
}

}  // namespace tofcomp::core
