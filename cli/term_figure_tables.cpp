#include "cli/term_figure_tables.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

namespace tofcomp::cli {
namespace {

constexpr int kCurvePoints = 400;     // linear over the covariate's span
constexpr int kCurveLogPoints = 200;  // and logarithmic for a covariate from zero (t_on)
constexpr int kRunLengths = 60;
constexpr int kDensityPoints = 800;
constexpr double kLeastPerBin = 10.0;  // ranges (in expectation) for an observed value

// A number for a CSV cell; empty for NaN (the renderer reads an empty cell as NaN).
std::string cell(double x) {
  return std::isfinite(x) ? fmt::format("{}", x) : std::string();
}

// Points over [lo, hi]: linear, and logarithmic from hi / 10⁴ when the covariate starts at zero
// (a decay in t_on is drawn on a logarithmic axis).
std::vector<double> curve_grid(double lo, double hi) {
  std::vector<double> x;
  for (int i = 0; i < kCurvePoints; ++i) x.push_back(lo + (hi - lo) * i / (kCurvePoints - 1));
  if (lo >= 0.0 && hi > 0.0) {
    const double from = std::log(hi * 1e-4), to = std::log(hi);
    for (int i = 0; i < kCurveLogPoints; ++i) {
      const double v = std::exp(from + (to - from) * i / (kCurveLogPoints - 1));
      if (v > lo && v < hi) x.push_back(v);
    }
  }
  std::sort(x.begin(), x.end());
  x.erase(std::unique(x.begin(), x.end()), x.end());
  return x;
}

double term_value(const core::MeanTermFit& fit, double covariate) {
  Eigen::RowVectorXd row(fit.term.columns());
  core::term_design_row(fit.term, covariate, row);
  return row.dot(fit.coefficients);
}

double normal_density(double x, double mean, double variance) {
  const double z = x - mean;
  return std::exp(-0.5 * z * z / variance) / std::sqrt(2.0 * std::numbers::pi * variance);
}

}  // namespace

std::string mean_term_ranges_csv(const SearchResiduals& r, const core::Term& term,
                                 const core::MeanTermFit* fit) {
  const Eigen::VectorXd c = r.covariates.values(term.covariate, term.time_constant_s);
  const Eigen::VectorXd own =
      fit ? Eigen::VectorXd(r.covariates.columns(fit->term) * fit->coefficients)
          : Eigen::VectorXd(Eigen::VectorXd::Zero(c.size()));
  std::string out = "covariate,partial_residual_mm,mode,in_term\n";
  for (Eigen::Index k = 0; k < c.size(); ++k) {
    const int mode = r.mode[k];
    const bool acts =
        mode != kOutlierMode && (term.parameter == core::Parameter::Bias || mode == term.mode);
    out += fmt::format("{},{},{},{}\n", c[k], acts ? cell(r.e[k] + own[k]) : std::string(), mode,
                       acts ? 1 : 0);
  }
  return out;
}

std::string mean_term_curve_csv(const SearchResiduals& r, const core::MeanTermFit& fit) {
  const Eigen::VectorXd c = r.covariates.values(fit.term.covariate, fit.term.time_constant_s);
  std::string out = "covariate,fitted_mm\n";
  for (const double x : curve_grid(c.minCoeff(), c.maxCoeff())) {
    out += fmt::format("{},{}\n", x, term_value(fit, x));
  }
  return out;
}

std::string bins_term_csv(const SearchResiduals& r, const core::Term& term,
                          const core::NoiseBins* fit) {
  const bool spread = term.parameter == core::Parameter::Spread;
  const Eigen::VectorXd c = r.covariates.values(term.covariate, term.time_constant_s);
  const Eigen::VectorXi bin = r.covariates.bins(term);
  const int bins = static_cast<int>(term.knots.size()) + 1;
  const int modes = r.mixture.modes.modes();
  const Eigen::MatrixXd& shift = r.compensation.mode_shift;
  std::string out = "bin,low,high,covariate_mean,mode,ranges,observed,fitted,held\n";
  for (int b = 0; b < bins; ++b) {
    const double low = b == 0 ? c.minCoeff() : term.knots[b - 1];
    const double high = b == bins - 1 ? c.maxCoeff() : term.knots[b];
    double covariate_sum = 0.0;
    Eigen::Index in_bin = 0;
    Eigen::VectorXd mass = Eigen::VectorXd::Zero(modes), square = Eigen::VectorXd::Zero(modes);
    for (Eigen::Index k = 0; k < c.size(); ++k) {
      if (bin[k] != b) continue;
      covariate_sum += c[k];
      ++in_bin;
      for (int i = 0; i < modes; ++i) {
        const double e =
            r.residual[k] - r.mixture.modes.mean[i] - (shift.size() > 0 ? shift(k, i) : 0.0);
        mass[i] += r.responsibility(k, i);
        square[i] += r.responsibility(k, i) * e * e;
      }
    }
    const double covariate_mean =
        in_bin > 0 ? covariate_sum / static_cast<double>(in_bin) : 0.5 * (low + high);
    for (int i = 0; i < modes; ++i) {
      double observed = std::nan(""), fitted = std::nan(""), held = std::nan("");
      if (spread) {
        if (mass[i] >= kLeastPerBin) observed = std::sqrt(square[i] / mass[i]);
        if (fit)
          fitted = std::sqrt(fit->table(b, i));
        else
          held = std::sqrt(r.mixture.modes.variance[i]);
      } else {
        if (mass.sum() >= kLeastPerBin) observed = mass[i] / mass.sum();
        if (fit)
          fitted = fit->table(b, i);
        else
          held = r.mixture.modes.weight[i];
      }
      out += fmt::format("{},{},{},{},{},{},{},{},{}\n", b + 1, low, high, covariate_mean, i + 1,
                         mass[i], cell(observed), cell(fitted), cell(held));
    }
  }
  return out;
}

std::string runs_csv(const SearchResiduals& r, const Eigen::MatrixXd* transition) {
  const int modes = r.mixture.modes.modes();
  // runs[i][L]: runs of mode i of length L (L ≤ kRunLengths; longer ones only in the total).
  std::vector<std::vector<long>> runs(static_cast<std::size_t>(modes),
                                      std::vector<long>(kRunLengths + 1, 0));
  std::vector<long> total(static_cast<std::size_t>(modes), 0);
  int longest = 1;
  const Eigen::Index n = r.mode.size();
  for (Eigen::Index start = 0; start < n;) {
    Eigen::Index end = start + 1;
    while (end < n && r.mode[end] == r.mode[start]) ++end;
    const int mode = r.mode[start];
    if (mode != kOutlierMode) {
      const auto length = static_cast<int>(end - start);
      longest = std::max(longest, length);
      ++total[static_cast<std::size_t>(mode)];
      if (length <= kRunLengths) ++runs[static_cast<std::size_t>(mode)][length];
    }
    start = end;
  }
  const int shown = std::min(longest, kRunLengths);
  std::string out = "mode,length,observed,chain,independent\n";
  for (int i = 0; i < modes; ++i) {
    const auto runs_of_mode = static_cast<double>(total[static_cast<std::size_t>(i)]);
    const double stay_independent = r.mixture.modes.weight[i];
    for (int length = 1; length <= shown; ++length) {
      const auto geometric = [&](double stay) {
        return runs_of_mode * (1.0 - stay) * std::pow(stay, length - 1);
      };
      out += fmt::format("{},{},{},{},{}\n", i + 1, length,
                         runs[static_cast<std::size_t>(i)][static_cast<std::size_t>(length)],
                         transition ? cell(geometric((*transition)(i, i))) : std::string(),
                         geometric(stay_independent));
    }
  }
  return out;
}

std::string density_csv(const SearchResiduals& r) {
  const core::ExtendedMixture& m = r.mixture;
  const int modes = m.modes.modes();
  const Eigen::Index n = r.residual.size();
  const double pad = 4.0 * std::sqrt(m.modes.variance.maxCoeff());
  const double lo = r.residual.minCoeff() - pad, hi = r.residual.maxCoeff() + pad;
  const bool shifted = r.compensation.mode_shift.size() > 0;
  const Eigen::VectorXi& state = r.compensation.noise_state;
  // The ranges of each noise state (without shifts, ranges of one state share one density).
  std::vector<double> share(static_cast<std::size_t>(m.states()), 0.0);
  for (Eigen::Index k = 0; k < n; ++k) share[static_cast<std::size_t>(state[k])] += 1.0 / n;
  const double gaussian_weight = 1.0 - m.outlier_weight;
  std::string out = "residual_mm";
  for (int i = 0; i < modes; ++i) out += fmt::format(",mode{}", i + 1);
  out += m.outlier_weight > 0.0 ? ",outliers,total\n" : ",total\n";
  for (int g = 0; g < kDensityPoints; ++g) {
    const double x = lo + (hi - lo) * g / (kDensityPoints - 1);
    double total = m.outlier_weight * m.outlier_density;
    out += cell(x);
    for (int i = 0; i < modes; ++i) {
      double density = 0.0;
      if (shifted) {
        for (Eigen::Index k = 0; k < n; ++k) {
          density += m.weight(state[k], i) *
                     normal_density(x, m.modes.mean[i] + r.compensation.mode_shift(k, i),
                                    m.variance(state[k], i));
        }
        density /= static_cast<double>(n);
      } else {
        for (int s = 0; s < m.states(); ++s) {
          if (share[static_cast<std::size_t>(s)] == 0.0) continue;
          density += share[static_cast<std::size_t>(s)] * m.weight(s, i) *
                     normal_density(x, m.modes.mean[i], m.variance(s, i));
        }
      }
      density *= gaussian_weight;
      total += density;
      out += "," + cell(density);
    }
    if (m.outlier_weight > 0.0) out += "," + cell(m.outlier_weight * m.outlier_density);
    out += "," + cell(total) + "\n";
  }
  return out;
}

std::string residuals_csv(const calibration::MeasuredData& measured, const SearchResiduals& r) {
  std::string out = "time_s,residual_mm,mode,e_mm\n";
  for (Eigen::Index k = 0; k < r.residual.size(); ++k) {
    out += fmt::format("{},{},{},{}\n", measured.range_time_s[k], r.residual[k], r.mode[k],
                       cell(r.e[k]));
  }
  return out;
}

}  // namespace tofcomp::cli
