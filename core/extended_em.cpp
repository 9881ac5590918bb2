#include "core/extended_em.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/covariate_table.hpp"
#include "core/error.hpp"
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

// w_ki = r_ki / σ²_{s(k),i}: the weights of the mean-structure and d steps.
Eigen::MatrixXd precision_weights(const Eigen::MatrixXd& r, const Eigen::VectorXi& state,
                                  const ExtendedMixture& m) {
  Eigen::MatrixXd w(r.rows(), r.cols());
  for (Eigen::Index k = 0; k < r.rows(); ++k) {
    for (Eigen::Index i = 0; i < r.cols(); ++i) {
      w(k, i) = r(k, i) / m.variance(state[k], static_cast<int>(i));
    }
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

// σ², π (per bin where the model has bins), the transition matrix and ε in closed form, from
// the residuals e_k = y_k − X_k θ and each mode's shifted offset.
void update_noise(const Eigen::VectorXd& e, const Eigen::MatrixXd& shift,
                  const Eigen::VectorXi& state, const ExtendedResponsibilities& r, double floor,
                  ExtendedMixture& m) {
  const int modes = m.modes.modes();
  const int variance_states = m.variance_states();
  Eigen::MatrixXd weight_mass = Eigen::MatrixXd::Zero(m.weight_states(), modes);
  Eigen::MatrixXd variance_mass = Eigen::MatrixXd::Zero(variance_states, modes);
  Eigen::MatrixXd square = Eigen::MatrixXd::Zero(variance_states, modes);
  const bool shifted = shift.size() > 0;
  for (Eigen::Index k = 0; k < e.size(); ++k) {
    const int weight_bin = state[k] / variance_states;
    const int variance_bin = state[k] % variance_states;
    for (int i = 0; i < modes; ++i) {
      const double centred = e[k] - m.modes.mean[i] - (shifted ? shift(k, i) : 0.0);
      const double resp = r.mode(k, i);
      weight_mass(weight_bin, i) += resp;
      variance_mass(variance_bin, i) += resp;
      square(variance_bin, i) += resp * centred * centred;
    }
  }
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

}  // namespace

Eigen::MatrixXd mode_shifts(const ExtendedDesign& design,
                            const std::vector<Eigen::VectorXd>& mode_coefficients) {
  const Eigen::Index k = design.state.size();
  Eigen::MatrixXd out;
  for (std::size_t i = 0; i < design.mode_columns.size(); ++i) {
    const Eigen::MatrixXd& z = design.mode_columns[i];
    if (z.size() == 0) continue;
    if (out.size() == 0) {
      out = Eigen::MatrixXd::Zero(k, static_cast<Eigen::Index>(design.mode_columns.size()));
    }
    out.col(static_cast<Eigen::Index>(i)) = z * mode_coefficients[i];
  }
  return out;
}

ExtendedEmResult train_extended_em(const ExtendedDesign& design,
                                   const Eigen::Ref<const Eigen::VectorXd>& y_minus_d,
                                   const ExtendedParameters& start,
                                   const ExtendedEmOptions& options) {
  require_finite(y_minus_d, "y - d");
  validate_design(design, y_minus_d.size(), start);
  start.model.validate();
  if (options.max_iterations < 1) throw InvalidInput("extended EM needs max_iterations >= 1");
  const Eigen::VectorXd y = y_minus_d;
  const auto k = static_cast<double>(y.size());

  ExtendedEmResult result;
  result.fit = start;
  Eigen::MatrixXd scratch;
  double previous = -std::numeric_limits<double>::infinity();
  for (;;) {
    const Eigen::MatrixXd shift = mode_shifts(design, result.fit.mode_coefficients);
    const double log_likelihood =
        extended_e_step(y - design.shared * result.fit.theta, design.state, shift,
                        result.fit.model, result.responsibilities);
    result.log_likelihood_trace.push_back(log_likelihood);
    result.log_likelihood = log_likelihood;
    if (std::abs(log_likelihood - previous) <= options.log_likelihood_tolerance * k) {
      result.converged = true;
      break;
    }
    if (result.iterations == options.max_iterations) break;
    previous = log_likelihood;
    // M-step: the mean structure at the previous variances, then the rest of the noise.
    const Eigen::MatrixXd w =
        precision_weights(result.responsibilities.mode, design.state, result.fit.model);
    MeanStructure solved =
        solve_mean_structure(design.shared, design.mode_columns, y, w, scratch);
    result.fit.theta = std::move(solved.theta);
    result.fit.model.modes.mean = std::move(solved.mean);
    result.fit.mode_coefficients = std::move(solved.mode_coefficients);
    update_noise(y - design.shared * result.fit.theta,
                 mode_shifts(design, result.fit.mode_coefficients), design.state,
                 result.responsibilities, options.variance_floor, result.fit.model);
    ++result.iterations;
  }
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
  double d = initial_distance ? *initial_distance : x.mean() - model.modes.mean_offset();
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
