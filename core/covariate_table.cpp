#include "core/covariate_table.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/thermal_model.hpp"
#include "core/validation.hpp"

namespace tofcomp::core {
namespace {

// The smooth form's knots sit at quantiles evenly spaced between these: the ends a little inside
// the range, so a few extreme values do not stretch the outer pieces.
constexpr double kFirstKnotQuantile = 0.02;
constexpr double kLastKnotQuantile = 0.98;
// A covariate whose standard deviation is below this share of its magnitude is constant.
constexpr double kRelativeConstantSpread = 1e-9;
// A parametric noise term's levels span f between the covariate's values at these quantiles
// (beyond them a range takes the end level).
constexpr std::array<double, 2> kLevelRangeQuantiles{0.005, 0.995};

// The covariate's values on `rows` (all when empty), in no particular order.
std::vector<double> values_on(const Eigen::VectorXd& v, const std::vector<Eigen::Index>& rows) {
  std::vector<double> out;
  if (rows.empty()) {
    out.assign(v.data(), v.data() + v.size());
  } else {
    out.reserve(rows.size());
    for (const Eigen::Index r : rows) out.push_back(v[r]);
  }
  return out;
}

// The q-quantile (the value at rank ⌊q (n − 1)⌋), selected in linear time: `values` is reordered,
// not changed, so several quantiles may be taken from it in turn (a term's τ profile makes a term
// at every point, and a full sort of a day's covariate each time cost more than the fits).
double quantile(std::vector<double>& values, double q) {
  const auto at = static_cast<std::size_t>(std::floor(q * static_cast<double>(values.size() - 1)));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(at), values.end());
  return values[at];
}

void require_increasing(const Eigen::VectorXd& knots, const Term& term);

// f(c) of a linear or decay term at one covariate value.
double design_value(const Term& term, double c) {
  Eigen::RowVectorXd row(1);
  term_design_row(term, c, row);
  return row[0];
}

// The edges, in the covariate's units, of kNoiseLevels levels equally spaced in f between f's
// values at the covariate's extreme quantiles.
Eigen::VectorXd level_edges(const Term& term, std::vector<double>& values) {
  const double c_lo = quantile(values, kLevelRangeQuantiles[0]);
  const double c_hi = quantile(values, kLevelRangeQuantiles[1]);
  if (!(c_hi > c_lo)) throw InvalidInput("term " + term.describe() + ": the covariate is constant");
  const double f_lo = design_value(term, c_lo), f_hi = design_value(term, c_hi);
  std::vector<double> edges;
  for (int j = 1; j < kNoiseLevels; ++j) {
    const double f = f_lo + (f_hi - f_lo) * static_cast<double>(j) / kNoiseLevels;
    // Back to the covariate: f = (c − centre)/scale, or f = exp(−c/τ).
    edges.push_back(term.form == Form::Linear ? term.centre + term.scale * f
                                              : -term.time_constant_s * std::log(f));
  }
  std::sort(edges.begin(), edges.end());
  Eigen::VectorXd out = Eigen::Map<const Eigen::VectorXd>(edges.data(), kNoiseLevels - 1);
  require_increasing(out, term);
  return out;
}

void require_increasing(const Eigen::VectorXd& knots, const Term& term) {
  for (Eigen::Index i = 1; i < knots.size(); ++i) {
    if (!(knots[i] > knots[i - 1])) {
      throw InvalidInput("term " + term.describe() + ": the covariate has too few distinct values");
    }
  }
}

}  // namespace

CovariateTable::CovariateTable(CovariateSeries series) : series_(std::move(series)) {
  const Eigen::Index n = series_.time_s.size();
  require_same_length(n, "time", series_.junction_c.size(), "junction temperature");
  require_same_length(n, "time", series_.time_since_power_on_s.size(), "time since power-on");
  if (series_.ambient_c.size() > 0) {
    require_same_length(n, "time", series_.ambient_c.size(), "ambient");
  }
  require_finite(series_.time_s, "time");
  require_finite(series_.junction_c, "junction temperature");
  require_finite(series_.time_since_power_on_s, "time since power-on");
  require_finite(series_.ambient_c, "ambient");
  for (Eigen::Index k = 1; k < n; ++k) {
    if (series_.time_s[k] < series_.time_s[k - 1]) {
      throw InvalidInput("covariates: time goes back at range " + std::to_string(k));
    }
  }
  if (series_.history_time_s.size() > 0) {
    require_same_length(series_.history_time_s.size(), "junction history time",
                        series_.history_junction_c.size(), "junction history");
    require_same_length(n, "time", series_.range_in_history.size(), "history index");
    require_finite(series_.history_junction_c, "junction history");
    for (Eigen::Index k = 0; k < n; ++k) {
      const int at = series_.range_in_history[k];
      if (at < 0 || at >= series_.history_time_s.size()) {
        throw InvalidInput("covariates: range " + std::to_string(k) +
                           " has no place in the junction's history");
      }
    }
  }
  if (series_.heating_rate_c_per_min.size() > 0) {
    require_same_length(n, "time", series_.heating_rate_c_per_min.size(), "heating rate");
    require_finite(series_.heating_rate_c_per_min, "heating rate");
    heating_rate_c_per_min_ = series_.heating_rate_c_per_min;
  } else {
    heating_rate_c_per_min_ =
        n > 0 ? Eigen::VectorXd(kSecondsPerMinute * local_rate(series_.time_s, series_.junction_c,
                                                               kHeatingRateHalfWindowS))
              : Eigen::VectorXd();
  }
}

bool CovariateTable::available(Covariate c) const {
  if (c == Covariate::None) return false;
  if (c == Covariate::Ambient) return series_.ambient_c.size() == size() && size() > 0;
  return true;
}

Eigen::VectorXd CovariateTable::values(Covariate c, double time_constant_s) const {
  if (!available(c)) {
    throw InvalidInput(std::string("covariate ") + covariate_token(c) +
                       " is not in these data (the ambient needs an ambient_c column)");
  }
  switch (c) {
    case Covariate::JunctionTemperature:
      return series_.junction_c;
    case Covariate::HeatingRate:
      return heating_rate_c_per_min_;
    case Covariate::TimeSincePowerOn:
      return series_.time_since_power_on_s;
    case Covariate::Time:
      return series_.time_s / 3600.0;
    case Covariate::Ambient:
      return series_.ambient_c;
    case Covariate::JunctionLag:
      return junction_lag(time_constant_s);
    case Covariate::None:
      break;
  }
  throw InvalidInput("no covariate");
}

Eigen::VectorXd CovariateTable::junction_lag(double time_constant_s) const {
  require_positive(time_constant_s, "the junction lag's time constant");
  if (series_.history_time_s.size() == 0) {
    return first_order_lag(series_.time_s, series_.junction_c, time_constant_s) -
           series_.junction_c;
  }
  const Eigen::VectorXd node =
      first_order_lag(series_.history_time_s, series_.history_junction_c, time_constant_s);
  Eigen::VectorXd out(size());
  for (Eigen::Index k = 0; k < size(); ++k) {
    const int at = series_.range_in_history[k];
    out[k] = node[at] - series_.history_junction_c[at];
  }
  return out;
}

Term CovariateTable::make_term(Parameter parameter, Covariate covariate, Form form, int mode,
                               double time_constant_s, const std::vector<Eigen::Index>& rows,
                               int smooth_knots) const {
  Term term;
  term.parameter = parameter;
  term.covariate = covariate;
  term.form = form;
  term.mode = mode;
  term.time_constant_s = time_constant_s;
  if (covariate == Covariate::None) {
    term.validate();
    return term;
  }
  const Eigen::VectorXd v = values(covariate, time_constant_s);
  std::vector<double> sample = values_on(v, rows);
  if (sample.size() < 2) throw InvalidInput("term " + term.describe() + ": too few ranges");
  if (form == Form::Linear) {
    double mean = 0.0;
    for (const double x : sample) mean += x;
    mean /= static_cast<double>(sample.size());
    double spread = 0.0;
    for (const double x : sample) spread += (x - mean) * (x - mean);
    spread = std::sqrt(spread / static_cast<double>(sample.size()));
    if (!(spread > kRelativeConstantSpread * std::max(1.0, std::abs(mean)))) {
      throw InvalidInput("term " + term.describe() + ": the covariate is constant");
    }
    term.centre = mean;
    term.scale = spread;
    // The time since the start is the one covariate that always leaves the range it was fitted
    // on, and a drift in it is meant to go on: it is not held.
    if (term.is_mean_term() && covariate != Covariate::Time) {
      const auto [low, high] = std::minmax_element(sample.begin(), sample.end());
      term.covariate_low = *low;
      term.covariate_high = *high;
    }
  } else if (form == Form::Smooth) {
    if (smooth_knots < kMinSmoothKnots || smooth_knots > kMaxSmoothKnots) {
      throw InvalidInput("term " + term.describe() + ": " + std::to_string(smooth_knots) +
                         " knots asked for, the smooth form takes " +
                         std::to_string(kMinSmoothKnots) + " to " +
                         std::to_string(kMaxSmoothKnots));
    }
    term.knots.resize(smooth_knots);
    const double quantile_span = kLastKnotQuantile - kFirstKnotQuantile;
    for (int i = 0; i < smooth_knots; ++i) {
      term.knots[i] = quantile(sample, kFirstKnotQuantile + quantile_span * i / (smooth_knots - 1));
    }
    require_increasing(term.knots, term);
  } else if (form == Form::Bins) {
    term.knots.resize(kCovariateBins - 1);
    for (int b = 1; b < kCovariateBins; ++b) {
      term.knots[b - 1] = quantile(sample, static_cast<double>(b) / kCovariateBins);
    }
    require_increasing(term.knots, term);
  }
  if (term.is_parametric_noise()) term.knots = level_edges(term, sample);
  term.validate();
  return term;
}

Eigen::MatrixXd CovariateTable::columns(const Term& term) const {
  const Eigen::VectorXd v = values(term.covariate, term.time_constant_s);
  Eigen::MatrixXd out(size(), term.columns());
  for (Eigen::Index k = 0; k < size(); ++k) term_design_row(term, v[k], out.row(k));
  return out;
}

Eigen::VectorXi CovariateTable::bins(const Term& term) const {
  const Eigen::VectorXd v = values(term.covariate, term.time_constant_s);
  Eigen::VectorXi out(size());
  for (Eigen::Index k = 0; k < size(); ++k) out[k] = term_bin(term, v[k]);
  return out;
}

void term_design_row(const Term& term, double c,
                     Eigen::Ref<Eigen::RowVectorXd, 0, Eigen::InnerStride<>> row) {
  switch (term.form) {
    case Form::Linear:
      row[0] = (std::clamp(c, term.covariate_low, term.covariate_high) - term.centre) / term.scale;
      return;
    case Form::Decay:
      row[0] = std::exp(-std::max(c, 0.0) / term.time_constant_s);
      return;
    case Form::Smooth: {
      // Hat functions on the knots, constant beyond the ends; the first hat is left out (the
      // hats sum to one, which the mode offsets already carry).
      const Eigen::VectorXd& kn = term.knots;
      const double x = std::clamp(c, kn[0], kn[kn.size() - 1]);
      row.setZero();
      for (Eigen::Index j = 1; j < kn.size(); ++j) {
        if (x <= kn[j]) {
          const double share = (x - kn[j - 1]) / (kn[j] - kn[j - 1]);
          row[j - 1] = share;
          if (j >= 2) row[j - 2] = 1.0 - share;
          return;
        }
      }
      return;
    }
    case Form::Bins:
    case Form::None:
      break;
  }
  throw InvalidInput("term " + term.describe() + " has no design columns");
}

Eigen::VectorXd noise_level_values(const Term& term) {
  const Eigen::Index edges = term.knots.size();
  if (!term.is_parametric_noise() || edges < 2) {
    throw InvalidInput("term " + term.describe() + " has no levels of f");
  }
  Eigen::VectorXd f(edges);
  for (Eigen::Index j = 0; j < edges; ++j) f[j] = design_value(term, term.knots[j]);
  Eigen::VectorXd out(edges + 1);
  out[0] = f[0] - 0.5 * (f[1] - f[0]);
  for (Eigen::Index l = 1; l < edges; ++l) out[l] = 0.5 * (f[l - 1] + f[l]);
  out[edges] = f[edges - 1] + 0.5 * (f[edges - 1] - f[edges - 2]);
  return out;
}

int term_bin(const Term& term, double c) {
  int b = 0;
  while (b < term.knots.size() && c >= term.knots[b]) ++b;
  return b;
}

Eigen::VectorXd local_rate(const Eigen::Ref<const Eigen::VectorXd>& time_s,
                           const Eigen::Ref<const Eigen::VectorXd>& value, double half_window_s) {
  require_same_length(time_s.size(), "time", value.size(), "value");
  require_positive(half_window_s, "rate half window");
  const Eigen::Index n = time_s.size();
  Eigen::VectorXd rate = Eigen::VectorXd::Zero(n);
  // Running sums over a window [lo, hi) that slides with k: O(K) overall.
  Eigen::Index lo = 0, hi = 0;
  double st = 0, sv = 0, stt = 0, stv = 0, count = 0;
  for (Eigen::Index k = 0; k < n; ++k) {
    while (hi < n && time_s[hi] <= time_s[k] + half_window_s) {
      const double t = time_s[hi] - time_s[0];
      st += t, sv += value[hi], stt += t * t, stv += t * value[hi], count += 1;
      ++hi;
    }
    while (time_s[lo] < time_s[k] - half_window_s) {
      const double t = time_s[lo] - time_s[0];
      st -= t, sv -= value[lo], stt -= t * t, stv -= t * value[lo], count -= 1;
      ++lo;
    }
    const double denominator = count * stt - st * st;
    rate[k] = denominator > 1e-9 * count * count ? (count * stv - st * sv) / denominator : 0.0;
  }
  return rate;
}

Eigen::VectorXd first_order_lag(const Eigen::Ref<const Eigen::VectorXd>& time_s,
                                const Eigen::Ref<const Eigen::VectorXd>& value,
                                double time_constant_s) {
  require_same_length(time_s.size(), "time", value.size(), "value");
  require_positive(time_constant_s, "lag time constant");
  Eigen::VectorXd out(value.size());
  if (value.size() == 0) return out;
  out[0] = value[0];
  for (Eigen::Index k = 1; k < value.size(); ++k) {
    const double decay = std::exp(-(time_s[k] - time_s[k - 1]) / time_constant_s);
    const double input = 0.5 * (value[k] + value[k - 1]);
    out[k] = input + decay * (out[k - 1] - input);
  }
  return out;
}

}  // namespace tofcomp::core
