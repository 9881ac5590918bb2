#include "core/residual_diagnosis.hpp"

#include <algorithm>
#include <boost/math/distributions/normal.hpp>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <random>
#include <utility>

#include "core/em_train.hpp"
#include "core/error.hpp"
#include "core/residual_statistics.hpp"
#include "core/validation.hpp"

namespace tofcomp::core {
namespace {

constexpr Eigen::Index kMinRanges = 100;
// A statistic is judged by its draws only when this share of them could be computed (the runs
// test needs two ranges of each label in a draw); else by its textbook law.
constexpr double kMinUsableDrawShare = 0.5;
// The median absolute deviation of a Gaussian is 0.6745 σ.
constexpr double kMadToSigma = 1.4826;
// A mode's robust scale at least this (mm), so that a mode on one rounded value has a bound.
constexpr double kSmallestScale = 1e-9;

Finding make(EffectKind kind, std::string test, std::string covariate, TestResult result,
             std::string reference) {
  Finding f;
  f.kind = kind;
  f.test = std::move(test);
  f.covariate = std::move(covariate);
  f.result = result;
  f.reference = std::move(reference);
  f.textbook_p_value = result.p_value;
  return f;
}

// One draw of the residual under the trained model: at each range a mode by its weight and a
// value from its Gaussian, the range rounded to the resolution as the device rounds it (the draw
// of y is round(d + H θ̂ + w), its residual that less d + H θ̂).
Eigen::VectorXd draw_residual(const Eigen::VectorXd& predicted_mm, const MixtureParameters& m,
                              double resolution_mm, std::uint64_t seed, Eigen::Index n) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> normal;
  Eigen::VectorXd cumulative(m.modes());
  double total = 0.0;
  for (int i = 0; i < m.modes(); ++i) cumulative[i] = total += m.weight[i];
  const Eigen::VectorXd sd = m.variance.cwiseSqrt();
  Eigen::VectorXd out(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const double u = uniform(rng) * total;
    int mode = 0;
    while (mode + 1 < m.modes() && u >= cumulative[mode]) ++mode;
    const double w = m.mean[mode] + sd[mode] * normal(rng);
    out[k] = resolution_mm > 0.0
                 ? resolution_mm * std::round((predicted_mm[k] + w) / resolution_mm) -
                       predicted_mm[k]
                 : w;
  }
  return out;
}

// SplitMix64's finalizer: well-spread seeds for the draws from one seed and the draw's index.
std::uint64_t draw_seed(std::uint64_t seed, int draw) {
  std::uint64_t z = seed + 0x9e3779b97f4a7c15ULL * static_cast<std::uint64_t>(draw + 1);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

struct Moments {
  double mean = 0.0;
  double sd = 0.0;
  int count = 0;
};

Moments moments(const std::vector<double>& values) {
  Moments m;
  m.count = static_cast<int>(values.size());
  if (m.count < 2) return m;
  for (double v : values) m.mean += v;
  m.mean /= m.count;
  double sum = 0.0;
  for (double v : values) sum += (v - m.mean) * (v - m.mean);
  m.sd = std::sqrt(sum / (m.count - 1));
  return m;
}

// The draws of one statistic judge it when enough of them exist and they spread at all.
bool judged_by_draws(const Moments& m, int draws) {
  return m.count >= kMinUsableDrawShare * draws && m.sd > 0.0;
}

// A signed statistic, normal under the model with the draws' mean and deviation: two-sided p,
// z its deviate; `fewer_is_positive` turns z for a statistic whose small values are the effect.
TestResult against_normal(TestResult observed, const Moments& m, bool fewer_is_positive = false) {
  const double z = (observed.statistic - m.mean) / m.sd;
  observed.p_value = two_sided_normal_p(z);
  observed.z = fewer_is_positive ? -z : std::abs(z);
  observed.degrees_of_freedom = 0.0;
  return observed;
}

// A χ²-like statistic against a scaled χ², a·χ²_ν with the draws' mean aν and variance 2a²ν
// (Satterthwaite's match of two moments; exact for a χ² statistic whose law is a χ²).
TestResult against_scaled_chi_square(TestResult observed, const Moments& m) {
  const double scale = m.sd * m.sd / (2.0 * m.mean);
  const double df = m.mean / scale;
  const double x = observed.statistic / scale;
  observed.p_value = chi_square_survival(x, df);
  observed.z = chi_square_to_z(x, df);
  observed.degrees_of_freedom = df;
  return observed;
}

// The draws' values of one statistic.
std::vector<double> values_of(const std::vector<ResidualStatistics>& draws,
                              TestResult ResidualStatistics::*statistic) {
  std::vector<double> out;
  for (const auto& d : draws) out.push_back((d.*statistic).statistic);
  return out;
}

// The same of a statistic some draws may lack (the runs test without two ranges of each label).
std::vector<double> values_of(const std::vector<ResidualStatistics>& draws,
                              std::optional<TestResult> ResidualStatistics::*statistic) {
  std::vector<double> out;
  for (const auto& d : draws) {
    if (d.*statistic) out.push_back((d.*statistic)->statistic);
  }
  return out;
}

// How the draws' moments judge a statistic: a signed one by the normal law (two-sided), one
// whose small values are the effect likewise with z turned (the runs' z), a χ²-like one by the
// scaled χ².
enum class DrawnLaw { Normal, NormalFewerIsPositive, ScaledChiSquare };

// The draws' reference, in the words the report prints.
std::string draws_reference(int draws, double resolution_mm) {
  std::string text = std::to_string(draws) + " draws of the trained model";
  if (resolution_mm > 0.0) {
    char unit[32];
    std::snprintf(unit, sizeof unit, ", rounded to %g mm", resolution_mm);
    text += unit;
  }
  return text;
}

// Each mode's spread in a scale outliers do not inflate: 1.4826 × the median of |r − μ_i| with
// each range weighted by its responsibility for mode i (Eq. 18). Under Eq. 8 the weighted ranges
// of a mode follow its Gaussian, so this is σ_i, overlap or not; where the EM widened a mode to
// hold outliers, its core still holds most of its weight and the median keeps the core's spread
// (2 % of ranges within ±100 mm made a two-mode fit's σ 11 mm where its core's is 0.8).
Eigen::VectorXd robust_mode_scales(const Eigen::VectorXd& residual, const MixtureParameters& m) {
  Eigen::MatrixXd responsibility;
  mixture_e_step(residual, m, responsibility);
  Eigen::VectorXd scale(m.modes());
  std::vector<std::pair<double, double>> weighted(static_cast<std::size_t>(residual.size()));
  for (int i = 0; i < m.modes(); ++i) {
    double total = 0.0;
    for (Eigen::Index k = 0; k < residual.size(); ++k) {
      weighted[static_cast<std::size_t>(k)] = {std::abs(residual[k] - m.mean[i]),
                                               responsibility(k, i)};
      total += responsibility(k, i);
    }
    std::sort(weighted.begin(), weighted.end());
    double below = 0.0, median = weighted.back().first;
    for (const auto& [deviation, weight] : weighted) {
      below += weight;
      if (below >= 0.5 * total) {
        median = deviation;
        break;
      }
    }
    scale[i] = std::max(kMadToSigma * median, kSmallestScale);
  }
  return scale;
}

// Of n values, how many lie beyond tail_z s_j (and half the rounding) of every lasing mode j, s_j
// its robust scale, and the probability of a value beyond tail_z s_j of every lasing mode under
// Gaussian lasing modes of those scales: for mode i, the mass of its Gaussian outside the union
// of the intervals μ_j ± tail_z s_j, summed over the gaps and the two ends on the tail's own side
// of μ_i (mode i's own interval holds μ_i, so every gap lies on one side of it), so that a
// probability of 1e-15 keeps its digits. A lasing mode spreads no more than the device's ranges
// do (max_lasing_spread_mm); a broader one the EM made to hold the outliers (a two-mode fit of
// the twin's 2 % outliers within ±100 mm: one mode for both lasing modes, σ 2.5 mm, and one of
// σ 47 mm and weight 1.5 %) is not a mode they are measured against. When no mode is that narrow,
// every mode is.
struct TailCount {
  double beyond = 0.0;
  double probability = 0.0;
  Eigen::VectorXd scale;
  std::vector<int> lasing;
};

TailCount tail_count(const Eigen::VectorXd& residual, const MixtureParameters& m, double tail_z,
                     double resolution_mm, double max_lasing_spread_mm) {
  TailCount out;
  out.scale = robust_mode_scales(residual, m);
  const Eigen::VectorXd& scale = out.scale;
  std::vector<int>& lasing = out.lasing;
  for (int i = 0; i < m.modes(); ++i) {
    if (scale[i] <= max_lasing_spread_mm) lasing.push_back(i);
  }
  if (lasing.empty()) {
    for (int i = 0; i < m.modes(); ++i) lasing.push_back(i);
  }
  double lasing_weight = 0.0;
  for (int i : lasing) lasing_weight += m.weight[i];
  std::vector<std::pair<double, double>> intervals;
  for (int j : lasing) {
    intervals.emplace_back(m.mean[j] - tail_z * scale[j], m.mean[j] + tail_z * scale[j]);
  }
  std::sort(intervals.begin(), intervals.end());
  std::vector<std::pair<double, double>> merged;
  for (const auto& iv : intervals) {
    if (!merged.empty() && iv.first <= merged.back().second) {
      merged.back().second = std::max(merged.back().second, iv.second);
    } else {
      merged.push_back(iv);
    }
  }
  const boost::math::normal standard;
  for (int i : lasing) {
    // Φ̄ of the standardized distance from μ_i, on whichever side the point lies.
    const auto beyond = [&](double x) {
      const double z = (x - m.mean[i]) / scale[i];
      return boost::math::cdf(boost::math::complement(standard, std::abs(z)));
    };
    double mass = beyond(merged.front().first) + beyond(merged.back().second);
    for (std::size_t g = 0; g + 1 < merged.size(); ++g) {
      mass += std::abs(beyond(merged[g].second) - beyond(merged[g + 1].first));
    }
    out.probability += m.weight[i] / lasing_weight * mass;
  }
  const double margin = 0.5 * resolution_mm;
  for (Eigen::Index k = 0; k < residual.size(); ++k) {
    bool far = true;
    for (std::size_t j = 0; j < lasing.size() && far; ++j) {
      const int mode = lasing[j];
      far = std::abs(residual[k] - m.mean[mode]) > tail_z * scale[mode] + margin;
    }
    out.beyond += far ? 1.0 : 0.0;
  }
  return out;
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
                                           double resolution_mm,
                                           const MixtureParameters* start = nullptr) {
  EmTrainOptions options;
  options.modes = modes;
  // No mode narrower than the rounding's own spread: a mode on one rounded value is the
  // lattice, not a lasing mode (as in training, calibration/training.cpp).
  options.variance_floor = resolution_mm * resolution_mm / 12.0;
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
// Rounded ranges are evaluated by the probability of their rounded value, not the density: where
// d + H θ̂ stands still (a junction at equilibrium) the residuals pile onto the rounding's
// lattice, and an M + 1st mode at the variance floor on one lattice value gained 50-70 nats of
// density on 10,000 ranges of Eq. 8 (p 1e-30 by universal inference, which holds only where the
// null is the data's law); the probability of a rounded value is the law rounded data have.
TestResult extra_mode_test(const Eigen::VectorXd& residual, const MixtureParameters& trained,
                           double resolution_mm) {
  const int modes = trained.modes();
  const Eigen::Index half = residual.size() / 2;
  const Eigen::VectorXd first = residual.head(half);
  const Eigen::VectorXd second = residual.tail(residual.size() - half);
  const auto log_t = [&](const Eigen::VectorXd& fit_on, const Eigen::VectorXd& test_on) {
    const auto alternative = fit_modes(fit_on, modes + 1, resolution_mm);
    const auto null = fit_modes(test_on, modes, resolution_mm, &trained);
    if (!alternative || !null) return -std::numeric_limits<double>::infinity();
    if (resolution_mm > 0.0) {
      const auto log_probability = [&](const MixtureParameters& fitted) {
        return rounded_mixture_log_probabilities(test_on, modes_before_rounding(fitted, resolution_mm),
                                                 resolution_mm)
            .sum();
      };
      return log_probability(*alternative) - log_probability(*null);
    }
    return mixture_log_likelihood(test_on, *alternative) - mixture_log_likelihood(test_on, *null);
  };
  const double a = log_t(first, second);
  const double b = log_t(second, first);
  const double top = std::max(a, b);
  const double log_mean =
      std::isfinite(top) ? top + std::log(0.5 * (std::exp(a - top) + std::exp(b - top))) : top;
  return split_likelihood_ratio_test(std::isfinite(log_mean) ? log_mean : 0.0);
}

// The warm-up's test: the correlation of e with exp(−t_on/τ) at each τ of the grid, the best
// τ's, Bonferroni over the grid (core/statistical_tests.hpp's best_correlation_test). Judged by
// the draws, each τ's r is standardized by its own draws' mean and deviation first.
Finding warm_up_finding(const ResidualStatistics& observed,
                        const std::vector<ResidualStatistics>& drawn, int draws,
                        const std::string& by_draws) {
  const auto taus = static_cast<double>(observed.warm_up.size());
  const char* test = "max correlation, 7 taus";
  const char* covariate = "exp(-time since power-on / tau)";
  std::vector<Moments> per_tau;
  bool by_draw = draws > 0;
  for (std::size_t c = 0; c < observed.warm_up.size() && by_draw; ++c) {
    std::vector<double> values;
    for (const auto& s : drawn) values.push_back(s.warm_up[c].statistic);
    per_tau.push_back(moments(values));
    by_draw = judged_by_draws(per_tau.back(), draws);
  }
  // The best τ by |z|, its z and the grid's Bonferroni p (two-sided: p = 2 Q(z); corrected,
  // Q(z') = taus × Q(z)), by the draws or by the textbook's z.
  const auto best_of = [&](bool standardized) {
    std::size_t best = 0;
    double best_z = -1.0;
    for (std::size_t c = 0; c < observed.warm_up.size(); ++c) {
      const double z = standardized ? std::abs(observed.warm_up[c].statistic - per_tau[c].mean) /
                                          per_tau[c].sd
                                    : observed.warm_up[c].z;
      if (z > best_z) best_z = z, best = c;
    }
    TestResult r = observed.warm_up[best];
    const double log_tail = std::log(taus) + log_upper_normal_tail(best_z);
    r.p_value = std::min(1.0, 2.0 * std::exp(log_tail));
    r.z = normal_deviate_of_log_p(log_tail);
    return std::pair{best, r};
  };
  const auto [best, result] = best_of(by_draw);
  Finding f = make(EffectKind::WarmUp, test, covariate, result, by_draw ? by_draws : "normal");
  f.textbook_p_value = best_of(false).second.p_value;
  if (by_draw) {
    f.null_mean = per_tau[best].mean;
    f.null_std = per_tau[best].sd;
  }
  return f;
}

std::string ljung_box_label(int lags) { return "lags 1.." + std::to_string(lags); }

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
  if (!(options.resolution_mm >= 0.0) || !std::isfinite(options.resolution_mm)) {
    throw InvalidInput("the diagnosis's resolution must be a finite number >= 0");
  }
  if (options.null_draws < 0) throw InvalidInput("the diagnosis's draws must be >= 0");
  if (options.resolution_mm > 0.0) {
    require_same_length(in.predicted_mm.size(), "predicted range", n, "residual");
    require_finite(in.predicted_mm, "predicted range");
  }

  const ResidualTestDesign design(in.time_s, in.junction_c, in.junction_rate_c_per_s,
                                  in.time_since_power_on_s, mixture,
                                  std::min<int>(options.ljung_box_lags, static_cast<int>(n / 4)));
  Diagnosis d;
  ModeAssignment assignment;
  const ResidualStatistics observed = design.statistics(in.residual, &assignment);
  d.mode = std::move(assignment.mode);
  d.compensated = std::move(assignment.compensated);
  d.standardized = std::move(assignment.standardized);

  // The trained model's draws, each from its own seed: the same draws whatever runs them.
  // The modes are drawn before the rounding (Sheppard's correction), then rounded.
  const int draws = options.null_draws;
  const MixtureParameters drawn_modes =
      options.resolution_mm > 0.0 ? modes_before_rounding(mixture, options.resolution_mm) : mixture;
  std::vector<ResidualStatistics> drawn(static_cast<std::size_t>(draws));
  const auto one_draw = [&](int b) {
    drawn[static_cast<std::size_t>(b)] = design.statistics(draw_residual(
        in.predicted_mm, drawn_modes, options.resolution_mm, draw_seed(options.seed, b), n));
  };
  if (options.parallel) {
    options.parallel(draws, one_draw);
  } else {
    for (int b = 0; b < draws; ++b) one_draw(b);
  }
  const std::string by_draws = draws_reference(draws, options.resolution_mm);

  // The finding of a statistic judged by its draws where they can, else by its textbook law.
  const auto judged = [&](EffectKind kind, const std::string& test, const std::string& covariate,
                          const TestResult& textbook, const char* textbook_law,
                          const std::vector<double>& values, DrawnLaw law) {
    const Moments m = moments(values);
    const bool chi_square = law == DrawnLaw::ScaledChiSquare;
    if (!judged_by_draws(m, draws) || (chi_square && !(m.mean > 0.0))) {
      Finding f = make(kind, test, covariate, textbook, textbook_law);
      if (law == DrawnLaw::NormalFewerIsPositive) f.result.z = -f.result.statistic;
      return f;
    }
    Finding f = make(kind, test, covariate,
                     chi_square ? against_scaled_chi_square(textbook, m)
                                : against_normal(textbook, m,
                                                 law == DrawnLaw::NormalFewerIsPositive),
                     by_draws);
    f.textbook_p_value = textbook.p_value;
    f.null_mean = m.mean;
    f.null_std = m.sd;
    return f;
  };

  if (observed.runs) {
    d.findings.push_back(judged(EffectKind::ModePersistence, "runs test",
                                "order of the modes in time", *observed.runs,
                                "the runs' normal law", values_of(drawn, &ResidualStatistics::runs),
                                DrawnLaw::NormalFewerIsPositive));
  }
  if (observed.weights) {
    d.findings.push_back(judged(EffectKind::TemperatureDependentWeights, "chi-square independence",
                                "junction temperature quartile", *observed.weights, "chi-square",
                                values_of(drawn, &ResidualStatistics::weights),
                                DrawnLaw::ScaledChiSquare));
  }
  // Rank correlation, so that a few large residuals do not pass for a change of spread.
  d.findings.push_back(judged(EffectKind::TemperatureDependentSpread, "Spearman correlation",
                              "junction temperature vs |z|", observed.spread, "normal",
                              values_of(drawn, &ResidualStatistics::spread), DrawnLaw::Normal));

  const TailCount tails = tail_count(in.residual, mixture, options.tail_z, options.resolution_mm,
                                     options.max_lasing_spread_mm);
  Finding outliers = make(
      EffectKind::Outliers, "tail excess", "|e - mu_i| > 8 robust sigma_i, all i",
      tail_excess_test(tails.beyond, static_cast<double>(n), tails.probability),
      "the modes' Gaussian tails");
  outliers.result.statistic = tails.beyond;  // the count, beside its expectation
  outliers.null_mean = tails.probability * static_cast<double>(n);
  d.findings.push_back(outliers);
  d.mode_scale_mm = tails.scale;
  d.lasing_modes = tails.lasing;
  d.resolution_mm = options.resolution_mm;

  d.findings.push_back(make(EffectKind::ExtraMode, "split likelihood ratio",
                            "M + 1 modes against M",
                            extra_mode_test(in.residual, mixture, options.resolution_mm),
                            "universal inference"));
  d.findings.push_back(judged(EffectKind::HeatingHysteresis, "correlation",
                              "junction heating rate", observed.heating, "normal",
                              values_of(drawn, &ResidualStatistics::heating), DrawnLaw::Normal));
  d.findings.push_back(judged(EffectKind::TimeDrift, "correlation", "time", observed.drift,
                              "normal", values_of(drawn, &ResidualStatistics::drift),
                              DrawnLaw::Normal));
  d.findings.push_back(warm_up_finding(observed, drawn, draws, by_draws));
  d.findings.push_back(judged(EffectKind::SerialDependence, "Ljung-Box",
                              ljung_box_label(design.ljung_box_lags()), observed.ljung_box,
                              "chi-square", values_of(drawn, &ResidualStatistics::ljung_box),
                              DrawnLaw::ScaledChiSquare));

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
