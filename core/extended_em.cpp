#include "core/extended_em.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <vector>

#include "core/column_products.hpp"
#include "core/covariate_table.hpp"
#include "core/em_train.hpp"
#include "core/error.hpp"
#include "core/extended_sweep.hpp"
#include "core/mode_regression.hpp"
#include "core/validation.hpp"

namespace tofcomp::core {
namespace {

constexpr double kMinimumMass = 1e-9;
// The outlier weight stays inside (0, ½]: a component that took more would not be outliers.
constexpr double kMinimumOutlierWeight = 1e-12;
constexpr double kMaximumOutlierWeight = 0.5;
// Newton's method on a parametric noise term's intercepts and slopes (a few parameters on the
// levels' sufficient statistics): at most this many steps, each halved at most this often, and
// stopped when no coordinate moves more than the tolerance.
constexpr int kSlopeNewtonSteps = 25;
constexpr int kSlopeHalvings = 30;
constexpr double kSlopeTolerance = 1e-10;
// EM testing's cold start under an outlier component: the window's mean over the ranges within
// the modes' reach of its median (the span of the offsets plus this many of the widest mode's
// standard deviations either side). A spurious return a metre out moves a 200-range mean by 5 mm,
// enough to start EM at a fixed point that takes a narrow mode for outliers.
constexpr double kStartReachDeviations = 6.0;

// w_ki = r_ki / σ²_{s(k),i}: the weights of the mean-structure and d steps; per mode a column
// product, with each range's spread bin gathered only when the spreads are binned.
Eigen::MatrixXd precision_weights(const Eigen::MatrixXd& r, const Eigen::VectorXi& state,
                                  const ExtendedMixture& m) {
  const int variance_states = m.variance_states();
  if (variance_states == 1) return r * m.modes.variance.cwiseInverse().asDiagonal();
  const Eigen::MatrixXd precision = m.variance_bins->table.cwiseInverse();  // bins × M
  Eigen::MatrixXd w(r.rows(), r.cols());
  Eigen::ArrayXd gathered(r.rows());
  for (Eigen::Index i = 0; i < r.cols(); ++i) {
    for (Eigen::Index k = 0; k < r.rows(); ++k) gathered[k] = precision(state[k] % variance_states, i);
    w.col(i) = (r.col(i).array() * gathered).matrix();
  }
  return w;
}

void require_mass(double mass, const std::string& what) {
  if (!(mass > kMinimumMass)) {
    throw NumericalError("extended EM: " + what +
                         " holds no range; the data do not support this extension");
  }
}

// The M-step of a weights term of the linear or decay form: the multinomial log-likelihood
// Σ_l Σ_i n_li log π_li, π_li ∝ exp(a_i + b_i f_l) (mode 1's a, b zero), maximized by Newton's
// method from the current intercepts and slopes on the levels' expected counts n_li. It is
// concave, so each Newton step that does not raise it is halved until it does.
void fit_weight_slopes(const Eigen::MatrixXd& counts, NoiseBins& bins) {
  const Eigen::VectorXd f = noise_level_values(bins.term);
  const Eigen::Index modes = counts.cols(), free = modes - 1;
  if (free == 0) return;
  const auto objective = [&](const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    double total = 0.0;
    for (Eigen::Index l = 0; l < f.size(); ++l) {
      const Eigen::ArrayXd eta = a.array() + b.array() * f[l];
      const double top = eta.maxCoeff();
      const double log_sum = top + std::log((eta - top).exp().sum());
      total += (counts.row(l).transpose().array() * (eta - log_sum)).sum();
    }
    return total;
  };
  Eigen::VectorXd a = bins.intercept, b = bins.slope;
  double current = objective(a, b);
  for (int iteration = 0; iteration < kSlopeNewtonSteps; ++iteration) {
    // Gradient and Hessian over (a_1..a_{M−1}, b_1..b_{M−1}).
    Eigen::VectorXd gradient = Eigen::VectorXd::Zero(2 * free);
    Eigen::MatrixXd hessian = Eigen::MatrixXd::Zero(2 * free, 2 * free);
    for (Eigen::Index l = 0; l < f.size(); ++l) {
      const Eigen::ArrayXd eta = a.array() + b.array() * f[l];
      const Eigen::ArrayXd e = (eta - eta.maxCoeff()).exp();
      const Eigen::VectorXd p = (e / e.sum()).matrix();
      const double n = counts.row(l).sum();
      const Eigen::Vector2d x(1.0, f[l]);
      for (Eigen::Index i = 1; i < modes; ++i) {
        const double residual = counts(l, i) - n * p[i];
        gradient[i - 1] += residual;
        gradient[free + i - 1] += residual * f[l];
        for (Eigen::Index j = 1; j < modes; ++j) {
          const double w = n * p[i] * ((i == j ? 1.0 : 0.0) - p[j]);
          for (int u = 0; u < 2; ++u) {
            for (int v = 0; v < 2; ++v) hessian(u * free + i - 1, v * free + j - 1) += w * x[u] * x[v];
          }
        }
      }
    }
    const Eigen::VectorXd step = hessian.ldlt().solve(gradient);
    if (!step.allFinite()) break;
    double length = 1.0;
    bool improved = false;
    for (int halving = 0; halving < kSlopeHalvings && !improved; ++halving, length *= 0.5) {
      Eigen::VectorXd a_next = a, b_next = b;
      a_next.tail(free) += length * step.head(free);
      b_next.tail(free) += length * step.tail(free);
      const double next = objective(a_next, b_next);
      if (next >= current) improved = true, a = a_next, b = b_next, current = next;
    }
    if (!improved || step.cwiseAbs().maxCoeff() < kSlopeTolerance) break;
  }
  bins.intercept = a;
  bins.slope = b;
  bins.refresh_table();
}

// The M-step of a spread term of the linear or decay form: for each mode, Σ_l [−½ m_l (v + s f_l)
// − ½ S_l exp(−v − s f_l)] (m_l the level's expected count, S_l its expected squared residual)
// maximized over the log-variance's intercept v and slope s by Newton's method (concave), then
// every variance held at or above the floor.
void fit_variance_slopes(const Eigen::MatrixXd& mass, const Eigen::MatrixXd& square, double floor,
                         NoiseBins& bins) {
  const Eigen::VectorXd f = noise_level_values(bins.term);
  for (Eigen::Index i = 0; i < mass.cols(); ++i) {
    require_mass(mass.col(i).sum(), "mode " + std::to_string(i + 1));
    const auto objective = [&](double v, double s) {
      double total = 0.0;
      for (Eigen::Index l = 0; l < f.size(); ++l) {
        const double eta = v + s * f[l];
        total += -0.5 * mass(l, i) * eta - 0.5 * square(l, i) * std::exp(-eta);
      }
      return total;
    };
    double v = bins.intercept[i], s = bins.slope[i], current = objective(v, s);
    for (int iteration = 0; iteration < kSlopeNewtonSteps; ++iteration) {
      Eigen::Vector2d gradient = Eigen::Vector2d::Zero();
      Eigen::Matrix2d hessian = Eigen::Matrix2d::Zero();
      for (Eigen::Index l = 0; l < f.size(); ++l) {
        const double excess = 0.5 * square(l, i) * std::exp(-(v + s * f[l]));
        const Eigen::Vector2d x(1.0, f[l]);
        gradient += (excess - 0.5 * mass(l, i)) * x;
        hessian -= excess * x * x.transpose();
      }
      const Eigen::Vector2d step = -hessian.ldlt().solve(gradient);
      if (!step.allFinite()) break;
      double length = 1.0;
      bool improved = false;
      for (int halving = 0; halving < kSlopeHalvings && !improved; ++halving, length *= 0.5) {
        const double next = objective(v + length * step[0], s + length * step[1]);
        if (next >= current) {
          improved = true, v += length * step[0], s += length * step[1], current = next;
        }
      }
      if (!improved || step.cwiseAbs().maxCoeff() < kSlopeTolerance) break;
    }
    bins.intercept[i] = v;
    bins.slope[i] = s;
  }
  bins.refresh_table();
  bins.table = bins.table.cwiseMax(floor);
}

// The noise M-step's sums over the ranges, per mode: its responsibility mass per weight bin and
// per spread bin, and Σ r_ki (e_k − μ_i − s_ki)² per spread bin.
struct NoiseSums {
  Eigen::MatrixXd weight_mass, variance_mass, square;  // bins × M
  explicit NoiseSums(const ExtendedMixture& m)
      : weight_mass(Eigen::MatrixXd::Zero(m.weight_states(), m.modes.modes())),
        variance_mass(Eigen::MatrixXd::Zero(m.variance_states(), m.modes.modes())),
        square(Eigen::MatrixXd::Zero(m.variance_states(), m.modes.modes())) {}
};

// Adds to the sums the ranges of e (residuals y_k − X_k θ), with each mode's shift s_ki (columns
// per mode, or empty: none), their states and responsibilities r_ki.
void add_noise_sums(const Eigen::Ref<const Eigen::VectorXd>& e,
                    const Eigen::Ref<const Eigen::MatrixXd>& shift,
                    const Eigen::Ref<const Eigen::VectorXi>& state,
                    const Eigen::Ref<const Eigen::MatrixXd>& r, const ExtendedMixture& m,
                    NoiseSums& sums) {
  const int modes = m.modes.modes();
  const int variance_states = m.variance_states();
  const int weight_states = m.weight_states();
  const bool shifted = shift.size() > 0;
  Eigen::ArrayXd weighted_square(e.size());
  for (int i = 0; i < modes; ++i) {
    // r_ki (e_k − μ_i − s_ki)² on arrays; summed per bin only where there are bins.
    const auto resp = r.col(i).array();
    weighted_square = e.array() - m.modes.mean[i];
    if (shifted) weighted_square -= shift.col(i).array();
    weighted_square = resp * weighted_square.square();
    if (variance_states == 1 && weight_states == 1) {
      const double mass = resp.sum();
      sums.weight_mass(0, i) += mass;
      sums.variance_mass(0, i) += mass;
      sums.square(0, i) += weighted_square.sum();
      continue;
    }
    for (Eigen::Index k = 0; k < e.size(); ++k) {
      const int weight_bin = state[k] / variance_states;
      const int variance_bin = state[k] % variance_states;
      sums.weight_mass(weight_bin, i) += resp[k];
      sums.variance_mass(variance_bin, i) += resp[k];
      sums.square(variance_bin, i) += weighted_square[k];
    }
  }
}

// σ², π (per bin where the model has bins), the transition matrix and ε in closed form, from the
// sums at the new mean structure and the responsibilities.
void update_noise(const NoiseSums& sums, const ExtendedResponsibilities& r, double floor,
                  ExtendedMixture& m) {
  const int modes = m.modes.modes();
  const int variance_states = m.variance_states();
  const Eigen::MatrixXd& weight_mass = sums.weight_mass;
  const Eigen::MatrixXd& variance_mass = sums.variance_mass;
  const Eigen::MatrixXd& square = sums.square;
  const Eigen::RowVectorXd mode_mass = variance_mass.colwise().sum();
  for (int i = 0; i < modes; ++i) {
    require_mass(mode_mass[i], "mode " + std::to_string(i + 1));
    m.modes.variance[i] = std::max(square.col(i).sum() / mode_mass[i], floor);
  }
  m.modes.weight = (mode_mass / mode_mass.sum()).transpose();
  if (m.variance_bins && m.variance_bins->term.is_parametric_noise()) {
    fit_variance_slopes(variance_mass, square, floor, *m.variance_bins);
  } else if (m.variance_bins) {
    for (int b = 0; b < variance_states; ++b) {
      for (int i = 0; i < modes; ++i) {
        require_mass(variance_mass(b, i),
                     "mode " + std::to_string(i + 1) + " in spread bin " + std::to_string(b + 1));
        m.variance_bins->table(b, i) = std::max(square(b, i) / variance_mass(b, i), floor);
      }
    }
  }
  if (m.weight_bins && m.weight_bins->term.is_parametric_noise()) {
    fit_weight_slopes(weight_mass, *m.weight_bins);
  } else if (m.weight_bins) {
    for (int b = 0; b < m.weight_states(); ++b) {
      require_mass(weight_mass.row(b).sum(), "weight bin " + std::to_string(b + 1));
      m.weight_bins->table.row(b) = weight_mass.row(b) / weight_mass.row(b).sum();
    }
  }
  if (m.transition.size() > 0) {
    for (int i = 0; i < modes; ++i) {
      const double leaving = r.transitions.row(i).sum();
      require_mass(leaving, "the transitions out of mode " + std::to_string(i + 1));
      m.transition.row(i) = r.transitions.row(i) / leaving;
    }
  }
  if (m.outlier_weight > 0.0) {
    m.outlier_weight =
        std::clamp(r.outlier.mean(), kMinimumOutlierWeight, kMaximumOutlierWeight);
  }
}

// add_noise_sums over the ranges chunk by chunk, each chunk's residuals and shifts at `at`
// computed in cache (the fused sweep's M-step; core/extended_sweep.hpp).
void add_noise_sums_by_chunk(const ExtendedDesign& design, const Eigen::VectorXd& y,
                             const ExtendedParameters& at, const Eigen::MatrixXd& r,
                             NoiseSums& sums) {
  const Eigen::Index k = y.size();
  const bool shifted = has_mode_columns(design);
  Eigen::VectorXd e(kExtendedSweepChunk);
  Eigen::MatrixXd shift(shifted ? kExtendedSweepChunk : 0,
                        shifted ? static_cast<Eigen::Index>(design.mode_columns.size()) : 0);
  for (Eigen::Index first = 0; first < k; first += kExtendedSweepChunk) {
    const Eigen::Index n = std::min(kExtendedSweepChunk, k - first);
    auto e_chunk = e.head(n);
    e_chunk = y.segment(first, n);
    subtract_product(design.shared.middleRows(first, n), at.theta, e_chunk);
    auto shift_chunk = shift.topRows(shifted ? n : 0);
    if (shifted) mode_shifts_of_rows(design, at.mode_coefficients, first, n, shift_chunk);
    add_noise_sums(e_chunk, shift_chunk, design.state.segment(first, n), r.middleRows(first, n),
                   at.model, sums);
  }
}

void validate_design(const ExtendedDesign& design, Eigen::Index k,
                     const ExtendedParameters& start) {
  require_same_length(design.shared.rows(), "the shared design (rows)", k, "y - d");
  require_same_length(design.state.size(), "noise states", k, "y - d");
  require_same_length(start.theta.size(), "theta", design.shared.cols(), "the shared design");
  require_finite(design.shared, "the shared design");
  const auto modes = static_cast<std::size_t>(start.model.modes.modes());
  if (design.mode_columns.size() != modes || start.mode_coefficients.size() != modes) {
    throw InvalidInput("extended EM: one column block and one coefficient vector per mode");
  }
  for (std::size_t i = 0; i < modes; ++i) {
    const Eigen::MatrixXd& z = design.mode_columns[i];
    if (z.size() > 0) require_same_length(z.rows(), "a mode's columns (rows)", k, "y - d");
    require_finite(z, "a mode's columns");
    if (start.mode_coefficients[i].size() != z.cols()) {
      throw InvalidInput("extended EM: mode " + std::to_string(i + 1) +
                         "'s coefficients do not match its columns");
    }
  }
  if (design.state.size() > 0 &&
      (design.state.minCoeff() < 0 || design.state.maxCoeff() >= start.model.states())) {
    throw InvalidInput("extended EM: a noise state is out of range");
  }
}

// Row-wise log-ratios log(a_rc / a_r,last) of a row-stochastic table, appended to out.
void append_log_ratios(const Eigen::MatrixXd& table, std::vector<double>& out) {
  for (Eigen::Index r = 0; r < table.rows(); ++r) {
    const double last = std::log(table(r, table.cols() - 1));
    for (Eigen::Index c = 0; c + 1 < table.cols(); ++c) out.push_back(std::log(table(r, c)) - last);
  }
}

// The inverse: each row the softmax of its log-ratios and a zero.
void read_log_ratios(const double*& in, Eigen::MatrixXd& table) {
  for (Eigen::Index r = 0; r < table.rows(); ++r) {
    Eigen::ArrayXd row(table.cols());
    for (Eigen::Index c = 0; c + 1 < table.cols(); ++c) row[c] = *in++;
    row[table.cols() - 1] = 0.0;
    row = (row - row.maxCoeff()).exp();
    table.row(r) = (row / row.sum()).matrix().transpose();
  }
}

// The parameters as one vector in which every point is a valid model (core/squarem.hpp): θ, the
// β_i, μ as they are; log variances (per mode and per spread bin); log-ratio weights (per mode,
// per weight bin) and transition rows; a parametric noise term's intercepts and slopes; the
// outlier weight's logit.
Eigen::VectorXd encode(const ExtendedParameters& x) {
  std::vector<double> v(x.theta.data(), x.theta.data() + x.theta.size());
  for (const Eigen::VectorXd& beta : x.mode_coefficients) v.insert(v.end(), beta.data(), beta.data() + beta.size());
  const ExtendedMixture& m = x.model;
  v.insert(v.end(), m.modes.mean.data(), m.modes.mean.data() + m.modes.mean.size());
  for (const double s2 : m.modes.variance) v.push_back(std::log(s2));
  // A parametric noise term's intercepts and slopes, which are unconstrained; its table follows.
  const auto append_slopes = [&v](const NoiseBins& b) {
    v.insert(v.end(), b.intercept.data(), b.intercept.data() + b.intercept.size());
    v.insert(v.end(), b.slope.data(), b.slope.data() + b.slope.size());
  };
  if (m.variance_bins && m.variance_bins->term.is_parametric_noise()) {
    append_slopes(*m.variance_bins);
  } else if (m.variance_bins) {
    for (const double s2 : m.variance_bins->table.reshaped()) v.push_back(std::log(s2));
  }
  append_log_ratios(m.modes.weight.transpose(), v);
  if (m.weight_bins && m.weight_bins->term.is_parametric_noise()) {
    append_slopes(*m.weight_bins);
  } else if (m.weight_bins) {
    append_log_ratios(m.weight_bins->table, v);
  }
  if (m.transition.size() > 0) append_log_ratios(m.transition, v);
  if (m.outlier_weight > 0.0) v.push_back(std::log(m.outlier_weight / (1.0 - m.outlier_weight)));
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

// The inverse of encode onto the structure of `like`, variances at or above the floor and the
// outlier weight inside its bounds. Empty when a coordinate is not finite.
std::optional<ExtendedParameters> decode(const Eigen::VectorXd& v, const ExtendedParameters& like,
                                         double floor) {
  if (!v.allFinite()) return std::nullopt;
  ExtendedParameters x = like;
  const double* in = v.data();
  const auto read = [&](auto& target) {
    for (auto& value : target.reshaped()) value = *in++;
  };
  read(x.theta);
  for (Eigen::VectorXd& beta : x.mode_coefficients) read(beta);
  ExtendedMixture& m = x.model;
  read(m.modes.mean);
  read(m.modes.variance);
  m.modes.variance = m.modes.variance.array().exp().max(floor).matrix();
  const auto read_slopes = [&](NoiseBins& b) {
    read(b.intercept);
    read(b.slope);
    b.refresh_table();
  };
  if (m.variance_bins && m.variance_bins->term.is_parametric_noise()) {
    read_slopes(*m.variance_bins);
    m.variance_bins->table = m.variance_bins->table.cwiseMax(floor);
  } else if (m.variance_bins) {
    read(m.variance_bins->table);
    m.variance_bins->table = m.variance_bins->table.array().exp().max(floor).matrix();
  }
  Eigen::MatrixXd weight = m.modes.weight.transpose();
  read_log_ratios(in, weight);
  m.modes.weight = weight.transpose();
  if (m.weight_bins && m.weight_bins->term.is_parametric_noise()) {
    read_slopes(*m.weight_bins);
  } else if (m.weight_bins) {
    read_log_ratios(in, m.weight_bins->table);
  }
  if (m.transition.size() > 0) read_log_ratios(in, m.transition);
  if (m.outlier_weight > 0.0) {
    m.outlier_weight =
        std::clamp(1.0 / (1.0 + std::exp(-*in++)), kMinimumOutlierWeight, kMaximumOutlierWeight);
  }
  if (!m.modes.variance.allFinite() ||
      (m.variance_bins && !m.variance_bins->table.allFinite()) ||
      (m.weight_bins && !m.weight_bins->table.allFinite())) {
    return std::nullopt;
  }
  return x;
}

// A point of the iteration: parameters and the E-step at them.
struct ExtendedIterate {
  ExtendedParameters parameters;
  ExtendedResponsibilities responsibilities;
  double log_likelihood = 0.0;
  ExtendedStepSums sums;  // the fused sweep's normal equations (empty on the generic path)
};

// The cold start of EM testing: mean(x) − Σ π_i μ_i, and under an outlier component the mean of
// the ranges within the modes' reach of the median (kStartReachDeviations).
double cold_start_distance(const Eigen::VectorXd& x, const ExtendedMixture& model) {
  if (!(model.outlier_weight > 0.0) || x.size() == 0) return x.mean() - model.modes.mean_offset();
  std::vector<double> sorted(x.data(), x.data() + x.size());
  const auto middle = sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2);
  std::nth_element(sorted.begin(), middle, sorted.end());
  const double median = *middle;
  const double reach = model.modes.mean.maxCoeff() - model.modes.mean.minCoeff() +
                       2.0 * kStartReachDeviations * std::sqrt(model.modes.variance.maxCoeff());
  double sum = 0.0;
  Eigen::Index count = 0;
  for (const double v : x) {
    if (std::abs(v - median) <= reach) sum += v, ++count;
  }
  return sum / static_cast<double>(count) - model.modes.mean_offset();  // the median is counted
}

}  // namespace

bool has_mode_columns(const ExtendedDesign& design) {
  return std::any_of(design.mode_columns.begin(), design.mode_columns.end(),
                     [](const Eigen::MatrixXd& z) { return z.size() > 0; });
}

void mode_shifts_of_rows(const ExtendedDesign& design,
                         const std::vector<Eigen::VectorXd>& mode_coefficients, Eigen::Index first,
                         Eigen::Index n, Eigen::Ref<Eigen::MatrixXd> out) {
  for (std::size_t i = 0; i < design.mode_columns.size(); ++i) {
    const Eigen::MatrixXd& z = design.mode_columns[i];
    const auto column = static_cast<Eigen::Index>(i);
    if (z.size() == 0) {
      out.col(column).setZero();
    } else {
      out.col(column).noalias() = z.middleRows(first, n) * mode_coefficients[i];
    }
  }
}

Eigen::MatrixXd mode_shifts(const ExtendedDesign& design,
                            const std::vector<Eigen::VectorXd>& mode_coefficients) {
  if (!has_mode_columns(design)) return {};
  const Eigen::Index k = design.state.size();
  Eigen::MatrixXd out(k, static_cast<Eigen::Index>(design.mode_columns.size()));
  mode_shifts_of_rows(design, mode_coefficients, 0, k, out);
  return out;
}

namespace {

bool plain_mixture(const ExtendedDesign& design, const ExtendedParameters& start) {
  return !start.model.has_extension() && !has_mode_columns(design);
}

// The plain model on train_em's fused sweep: the same ECM step (θ and μ jointly by weighted least
// squares, then σ² and π in closed form), stopped by the same rule on the likelihood (the
// paper's rule on the weights off), a mode left with no range refused as the generic iteration
// refuses it, the modes kept in the start's order.
ExtendedEmResult train_plain_mixture(const ExtendedDesign& design,
                                     const Eigen::Ref<const Eigen::VectorXd>& y,
                                     const ExtendedParameters& start,
                                     const ExtendedEmOptions& options) {
  EmTrainOptions em;
  em.modes = start.model.modes.modes();
  em.start = EmStartingPoint{start.theta, start.model.modes};
  em.max_iterations = options.max_iterations;
  em.log_likelihood_tolerance = options.log_likelihood_tolerance;
  em.weight_tolerance = kWeightRuleOff;
  em.variance_floor = options.variance_floor;
  em.min_mode_weight = kMinimumMass / static_cast<double>(y.size());
  em.record_trace = true;
  em.acceleration = options.acceleration;
  em.sort_modes = false;
  EmTrainResult fit = train_em(design.shared, y, em);
  ExtendedEmResult out;
  out.fit = start;
  out.fit.theta = std::move(fit.theta);
  out.fit.model.modes = std::move(fit.mixture);
  out.responsibilities.mode = std::move(fit.responsibilities);
  out.responsibilities.outlier = Eigen::VectorXd::Zero(y.size());
  out.log_likelihood = fit.log_likelihood;
  out.iterations = fit.iterations;
  out.converged = fit.converged;
  for (const EmIterationRecord& row : fit.trace) out.log_likelihood_trace.push_back(row.log_likelihood);
  return out;
}

}  // namespace

ExtendedEmResult train_extended_em(const ExtendedDesign& design,
                                   const Eigen::Ref<const Eigen::VectorXd>& y_minus_d,
                                   const ExtendedParameters& start,
                                   const ExtendedEmOptions& options) {
  require_finite(y_minus_d, "y - d");
  validate_design(design, y_minus_d.size(), start);
  start.model.validate();
  if (options.max_iterations < 1) throw InvalidInput("extended EM needs max_iterations >= 1");
  if (options.fused_sweeps && plain_mixture(design, start)) {
    return train_plain_mixture(design, y_minus_d, start, options);
  }
  const Eigen::VectorXd y = y_minus_d;
  const auto k = static_cast<double>(y.size());
  // Independent draws run on the fused sweep (core/extended_sweep.hpp): the same ECM step.
  const bool fused = options.fused_sweeps && extended_sweep_applies(start.model);
  Eigen::RowVectorXd centre = design.shared.colwise().mean();

  ExtendedEmResult result;
  Eigen::MatrixXd scratch;
  // E-step at the parameters (the extended mixture's, core/extended_mixture.hpp).
  const auto evaluate = [&](ExtendedParameters parameters) {
    ExtendedIterate out;
    out.parameters = std::move(parameters);
    if (fused) {
      out.sums = extended_step_sweep(design, y, out.parameters, centre, out.responsibilities);
      out.log_likelihood = out.sums.log_likelihood;
      centre = out.sums.weighted_mean();
      return out;
    }
    const Eigen::MatrixXd shift = mode_shifts(design, out.parameters.mode_coefficients);
    out.log_likelihood =
        extended_e_step(y - design.shared * out.parameters.theta, design.state, shift,
                        out.parameters.model, out.responsibilities);
    return out;
  };
  // M-step from a point: the mean structure at its variances, then the rest of the noise.
  const auto step = [&](const ExtendedIterate& from) {
    ExtendedParameters next = from.parameters;
    MeanStructure solved =
        fused ? solve_mean_structure(from.sums.gram, from.sums.gram_rhs, from.sums.centre,
                                     from.sums.blocks)
              : solve_mean_structure(design.shared, design.mode_columns, y,
                                     precision_weights(from.responsibilities.mode, design.state,
                                                       from.parameters.model),
                                     scratch);
    next.theta = std::move(solved.theta);
    next.model.modes.mean = std::move(solved.mean);
    next.mode_coefficients = std::move(solved.mode_coefficients);
    NoiseSums sums(next.model);
    if (fused) {
      add_noise_sums_by_chunk(design, y, next, from.responsibilities.mode, sums);
    } else {
      add_noise_sums(y - design.shared * next.theta, mode_shifts(design, next.mode_coefficients),
                     design.state, from.responsibilities.mode, next.model, sums);
    }
    update_noise(sums, from.responsibilities, options.variance_floor, next.model);
    return next;
  };

  ExtendedIterate point = evaluate(start);
  double previous = -std::numeric_limits<double>::infinity();
  const auto arrive = [&](ExtendedIterate&& next) {
    previous = point.log_likelihood;
    point = std::move(next);
    result.log_likelihood_trace.push_back(point.log_likelihood);
  };
  result.log_likelihood_trace.push_back(point.log_likelihood);
  const auto done = [&] {
    if (std::abs(point.log_likelihood - previous) <= options.log_likelihood_tolerance * k) {
      result.converged = true;
      return true;
    }
    return result.iterations >= options.max_iterations;
  };
  const bool accelerate = options.acceleration == EmAcceleration::Squarem;
  SquaremSteps steps;
  // Under SQUAREM, the M-step from an extrapolated point is taken when the point is tried (a point
  // whose M-step fails is refused), and used by the next cycle.
  std::optional<ExtendedParameters> pending;
  const auto next_step = [&] {
    ++result.iterations;
    if (pending) {
      ExtendedParameters out = std::move(*pending);
      pending.reset();
      return out;
    }
    return step(point);
  };
  while (!done()) {
    if (!accelerate) {
      arrive(evaluate(next_step()));
      continue;
    }
    // SQUAREM: x0 → x1 → x2 by the map, then the extrapolated point, kept when valid and not
    // below x1's log-likelihood; x2 otherwise.
    const Eigen::VectorXd x0 = encode(point.parameters);
    arrive(evaluate(next_step()));
    if (done()) break;
    const Eigen::VectorXd x1 = encode(point.parameters);
    ExtendedParameters x2 = next_step();
    const Eigen::VectorXd r = x1 - x0;
    const Eigen::VectorXd v = encode(x2) - x1 - r;
    const double alpha = steps.step_length(r, v);
    if (alpha > 1.0) {
      if (std::optional<ExtendedParameters> jump =
              decode(SquaremSteps::extrapolate(x0, r, v, alpha), x2, options.variance_floor)) {
        try {
          ExtendedIterate tried = evaluate(std::move(*jump));
          if (tried.log_likelihood >= point.log_likelihood) {
            pending = step(tried);
            steps.accepted(alpha);
            arrive(std::move(tried));
            continue;
          }
        } catch (const NumericalError&) {
          // The extrapolated point has no finite likelihood or its M-step fails: refused.
        }
      }
      steps.refused(alpha);
    } else {
      steps.accepted(alpha);
    }
    arrive(evaluate(std::move(x2)));
  }
  result.fit = std::move(point.parameters);
  result.responsibilities = std::move(point.responsibilities);
  result.log_likelihood = point.log_likelihood;
  return result;
}

EmTestResult test_extended_em(const Eigen::Ref<const Eigen::VectorXd>& y,
                              const Eigen::Ref<const Eigen::VectorXd>& bias,
                              const Eigen::Ref<const Eigen::VectorXi>& state_in,
                              const Eigen::Ref<const Eigen::MatrixXd>& shift_in,
                              const ExtendedMixture& model, const EmTestOptions& options,
                              std::optional<double> initial_distance) {
  validate_test_arguments(y, bias, options, initial_distance);
  require_same_length(y.size(), "y", state_in.size(), "noise states");
  model.validate();
  const Eigen::VectorXd x = y - bias;
  const Eigen::VectorXi state = state_in;
  const Eigen::MatrixXd shift = shift_in;
  const bool shifted = shift.size() > 0;
  ExtendedResponsibilities r;
  EmTestResult result;
  double d = initial_distance ? *initial_distance : cold_start_distance(x, model);
  d = iterate_distance(
      d, options, result,
      [&](double at) { return extended_e_step(x.array() - at, state, shift, model, r); },
      [&] {
        const Eigen::MatrixXd w = precision_weights(r.mode, state, model);
        const double total = w.sum();
        if (!(total > 0.0)) {
          throw NumericalError("EM testing: every range of the window is taken for an outlier");
        }
        double offsets = w.colwise().sum().dot(model.modes.mean);
        if (shifted) offsets += w.cwiseProduct(shift).sum();
        return (w.rowwise().sum().dot(x) - offsets) / total;
      });
  result.distance = d;
  Eigen::MatrixXd precision(x.size(), model.modes.modes());
  for (Eigen::Index k = 0; k < x.size(); ++k) {
    for (int i = 0; i < model.modes.modes(); ++i) precision(k, i) = 1.0 / model.variance(state[k], i);
  }
  result.distance_std = distance_standard_deviation(x, d, r.mode, model.modes.mean, precision, shift);
  result.responsibilities = std::move(r.mode);
  return result;
}

}  // namespace tofcomp::core
