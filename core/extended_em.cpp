#include "core/extended_em.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/error.hpp"
#include "core/mode_regression.hpp"
#include "core/validation.hpp"

namespace tofcomp::core {
namespace {

constexpr double kMinimumMass = 1e-9;

// w_ki = r_ki / σ²_{b(k),i}: the weights of the (θ, μ) and d steps.
Eigen::MatrixXd precision_weights(const Eigen::MatrixXd& r, const Eigen::VectorXi& bin,
                                  const ExtendedMixture& m) {
  Eigen::MatrixXd w(r.rows(), r.cols());
  for (Eigen::Index k = 0; k < r.rows(); ++k) {
    for (Eigen::Index i = 0; i < r.cols(); ++i) {
      w(k, i) = r(k, i) / m.variance(bin[k], static_cast<int>(i));
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

// σ², π (per bin where the model has bins), the transition matrix and ε in closed form.
void update_noise(const Eigen::VectorXd& e, const Eigen::VectorXi& bin,
                  const ExtendedResponsibilities& r, double floor, ExtendedMixture& m) {
  const int modes = m.modes.modes();
  const int bins = m.bins();
  Eigen::MatrixXd mass = Eigen::MatrixXd::Zero(bins, modes);
  Eigen::MatrixXd square = Eigen::MatrixXd::Zero(bins, modes);
  for (Eigen::Index k = 0; k < e.size(); ++k) {
    for (int i = 0; i < modes; ++i) {
      const double centred = e[k] - m.modes.mean[i];
      mass(bin[k], i) += r.mode(k, i);
      square(bin[k], i) += r.mode(k, i) * centred * centred;
    }
  }
  const Eigen::RowVectorXd mode_mass = mass.colwise().sum();
  for (int i = 0; i < modes; ++i) {
    require_mass(mode_mass[i], "mode " + std::to_string(i + 1));
    m.modes.variance[i] = std::max(square.col(i).sum() / mode_mass[i], floor);
  }
  m.modes.weight = (mode_mass / mode_mass.sum()).transpose();
  if (m.bin_variance.size() > 0) {
    for (int b = 0; b < bins; ++b) {
      for (int i = 0; i < modes; ++i) {
        require_mass(mass(b, i), "mode " + std::to_string(i + 1) + " in temperature bin " +
                                     std::to_string(b + 1));
        m.bin_variance(b, i) = std::max(square(b, i) / mass(b, i), floor);
      }
    }
  }
  if (m.bin_weight.size() > 0) {
    for (int b = 0; b < bins; ++b) {
      require_mass(mass.row(b).sum(), "temperature bin " + std::to_string(b + 1));
      m.bin_weight.row(b) = mass.row(b) / mass.row(b).sum();
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
    m.outlier_weight = std::clamp(r.outlier.mean(), 1e-12, 0.5);
  }
}

}  // namespace

ExtendedEmResult train_extended_em(const Eigen::Ref<const Eigen::MatrixXd>& h,
                                   const Eigen::Ref<const Eigen::VectorXd>& y_minus_d,
                                   const Eigen::Ref<const Eigen::VectorXi>& bin_in,
                                   const Eigen::VectorXd& theta_start, const ExtendedMixture& start,
                                   const ExtendedEmOptions& options) {
  require_same_length(h.rows(), "H (rows)", y_minus_d.size(), "y - d");
  require_same_length(theta_start.size(), "theta", h.cols(), "H (columns)");
  require_finite(h, "H");
  require_finite(y_minus_d, "y - d");
  start.validate();
  if (options.max_iterations < 1) throw InvalidInput("extended EM needs max_iterations >= 1");
  const Eigen::VectorXd y = y_minus_d;
  const Eigen::VectorXi bin = bin_in;
  const auto k = static_cast<double>(y.size());

  ExtendedEmResult result;
  result.theta = theta_start;
  result.model = start;
  Eigen::MatrixXd scratch;
  double previous = -std::numeric_limits<double>::infinity();
  for (;;) {
    const double log_likelihood =
        extended_e_step(y - h * result.theta, bin, result.model, result.responsibilities);
    result.log_likelihood_trace.push_back(log_likelihood);
    result.log_likelihood = log_likelihood;
    if (std::abs(log_likelihood - previous) <= options.log_likelihood_tolerance * k) {
      result.converged = true;
      break;
    }
    if (result.iterations == options.max_iterations) break;
    previous = log_likelihood;
    // M-step: (θ, μ) at the previous variances, then the rest of the noise.
    const Eigen::MatrixXd w = precision_weights(result.responsibilities.mode, bin, result.model);
    BiasAndOffsets solved = solve_bias_and_offsets(h, y, w, scratch);
    result.theta = std::move(solved.theta);
    result.model.modes.mean = std::move(solved.mean);
    update_noise(y - h * result.theta, bin, result.responsibilities, options.variance_floor,
                 result.model);
    ++result.iterations;
  }
  return result;
}

EmTestResult test_extended_em(const Eigen::Ref<const Eigen::VectorXd>& y,
                              const Eigen::Ref<const Eigen::VectorXd>& bias,
                              const Eigen::Ref<const Eigen::VectorXi>& bin_in,
                              const ExtendedMixture& model, const EmTestOptions& options,
                              std::optional<double> initial_distance) {
  validate_test_arguments(y, bias, options, initial_distance);
  require_same_length(y.size(), "y", bin_in.size(), "temperature bins");
  model.validate();
  const Eigen::VectorXd x = y - bias;
  const Eigen::VectorXi bin = bin_in;
  ExtendedResponsibilities r;
  EmTestResult result;
  double d = initial_distance ? *initial_distance : x.mean() - model.modes.mean_offset();
  d = iterate_distance(
      d, options, result, [&](double at) { return extended_e_step(x.array() - at, bin, model, r); },
      [&] {
        const Eigen::MatrixXd w = precision_weights(r.mode, bin, model);
        const double total = w.sum();
        if (!(total > 0.0)) {
          throw NumericalError("EM testing: every range of the window is taken for an outlier");
        }
        return (w.rowwise().sum().dot(x) - w.colwise().sum().dot(model.modes.mean)) / total;
      });
  result.distance = d;
  Eigen::MatrixXd precision(x.size(), model.modes.modes());
  for (Eigen::Index k = 0; k < x.size(); ++k) {
    for (int i = 0; i < model.modes.modes(); ++i) precision(k, i) = 1.0 / model.variance(bin[k], i);
  }
  result.distance_std = distance_standard_deviation(x, d, r.mode, model.modes.mean, precision);
  result.responsibilities = std::move(r.mode);
  return result;
}

Eigen::VectorXd quantile_edges(const Eigen::Ref<const Eigen::VectorXd>& values, int bins) {
  if (bins < 1) throw InvalidInput("quantile edges need at least one bin");
  if (values.size() < bins) throw InvalidInput("fewer values than bins");
  require_finite(values, "values");
  std::vector<double> sorted(values.data(), values.data() + values.size());
  std::sort(sorted.begin(), sorted.end());
  Eigen::VectorXd edges(bins - 1);
  for (int b = 1; b < bins; ++b) {
    edges[b - 1] = sorted[static_cast<std::size_t>(sorted.size() * static_cast<std::size_t>(b) /
                                                   static_cast<std::size_t>(bins))];
  }
  for (Eigen::Index b = 1; b < edges.size(); ++b) {
    if (!(edges[b] > edges[b - 1])) {
      throw InvalidInput("the values have too few distinct levels for " + std::to_string(bins) +
                         " bins");
    }
  }
  return edges;
}

}  // namespace tofcomp::core
