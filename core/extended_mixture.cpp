#include "core/extended_mixture.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include "core/covariate_table.hpp"
#include "core/error.hpp"
#include "core/validation.hpp"
#include "core/vector_math.hpp"

namespace tofcomp::core {
namespace {

constexpr double kRowSumTolerance = 1e-9;
constexpr double kMinusInfinity = -std::numeric_limits<double>::infinity();

void require_stochastic_rows(const Eigen::MatrixXd& m, const char* what) {
  require_finite(m, what);
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    if ((m.row(r).array() < 0.0).any() || std::abs(m.row(r).sum() - 1.0) > kRowSumTolerance) {
      std::ostringstream msg;
      msg << what << ": row " << r + 1 << " must be non-negative and sum to 1 (sums to "
          << m.row(r).sum() << ")";
      throw InvalidInput(msg.str());
    }
  }
}

void require_shape(const Eigen::MatrixXd& m, Eigen::Index rows, Eigen::Index cols,
                   const char* what) {
  if (m.rows() != rows || m.cols() != cols) {
    std::ostringstream msg;
    msg << what << " is " << m.rows() << " x " << m.cols() << ": it must be " << rows << " x "
        << cols;
    throw InvalidInput(msg.str());
  }
}

void validate_bins(const NoiseBins& bins, Parameter parameter, int modes, const char* what) {
  if (bins.term.parameter != parameter) {
    throw InvalidInput(std::string(what) + ": the term is " + bins.term.describe());
  }
  bins.term.validate();
  require_shape(bins.table, bins.bins(), modes, what);
  if (bins.term.is_parametric_noise()) {
    if (bins.intercept.size() != modes || bins.slope.size() != modes) {
      throw InvalidInput(std::string(what) + ": a parametric term needs an intercept and a slope "
                                             "per mode");
    }
    require_finite(bins.intercept, "intercepts");
    require_finite(bins.slope, "slopes");
  } else if (bins.intercept.size() > 0 || bins.slope.size() > 0) {
    throw InvalidInput(std::string(what) + ": bins take no intercept or slope");
  }
}

double log_of(double p) { return p > 0.0 ? std::log(p) : kMinusInfinity; }

// log N(e; μ_i + shift_ki, σ²_{s,i}) (or with resolution h, the log-probability of the rounded
// value) for every range (rows) and mode (columns), without the prior.
void log_emission(const Eigen::Ref<const Eigen::VectorXd>& e,
                  const Eigen::Ref<const Eigen::VectorXi>& state,
                  const Eigen::Ref<const Eigen::MatrixXd>& shift, const ExtendedMixture& m,
                  double resolution, Eigen::MatrixXd& out) {
  const int modes = m.modes.modes();
  const bool shifted = shift.size() > 0;
  out.resize(e.size(), modes);
  if (resolution > 0.0) {
    // Column by column: each range's mean and spread under mode i, then the rounded value's
    // log-probability on arrays.
    Eigen::ArrayXd mean(e.size()), variance(e.size());
    for (int i = 0; i < modes; ++i) {
      for (Eigen::Index k = 0; k < e.size(); ++k) {
        mean[k] = m.modes.mean[i] + (shifted ? shift(k, i) : 0.0);
        variance[k] = m.variance(state[k], i);
      }
      out.col(i) = rounded_normal_log_probabilities(e.array(), mean, variance, resolution).matrix();
    }
    return;
  }
  // −½ log(2π σ²) and 1/(2σ²) of each spread bin and mode, computed once; per range gathered
  // by its bin only when the spreads are binned.
  const int variance_states = m.variance_states();
  Eigen::MatrixXd log_norm(variance_states, modes), half_precision(variance_states, modes);
  for (int b = 0; b < variance_states; ++b) {
    for (int i = 0; i < modes; ++i) {
      const double variance = m.variance(b, i);  // state b: weight bin 0, spread bin b
      log_norm(b, i) = -0.5 * std::log(2.0 * std::numbers::pi * variance);
      half_precision(b, i) = 0.5 / variance;
    }
  }
  Eigen::ArrayXd centred(e.size()), gathered_norm, gathered_precision;
  if (variance_states > 1) {
    gathered_norm.resize(e.size());
    gathered_precision.resize(e.size());
  }
  for (int i = 0; i < modes; ++i) {
    centred = e.array() - m.modes.mean[i];
    if (shifted) centred -= shift.col(i).array();
    if (variance_states == 1) {
      out.col(i) = (log_norm(0, i) - centred.square() * half_precision(0, i)).matrix();
      continue;
    }
    for (Eigen::Index k = 0; k < e.size(); ++k) {
      const int bin = state[k] % variance_states;
      gathered_norm[k] = log_norm(bin, i);
      gathered_precision[k] = half_precision(bin, i);
    }
    out.col(i) = (gathered_norm - centred.square() * gathered_precision).matrix();
  }
}

// Independent draws (with bin weights and the outlier component): a log-sum-exp per range, on
// Eigen arrays over all ranges (vectorized exp and log). Fills the per-range log-likelihoods
// when asked.
double independent_e_step(const Eigen::Ref<const Eigen::VectorXi>& state, const ExtendedMixture& m,
                          double log_outlier_density, Eigen::MatrixXd& log_joint,
                          ExtendedResponsibilities& out, Eigen::VectorXd* per_range) {
  const Eigen::Index k_count = log_joint.rows();
  const int modes = m.modes.modes();
  const double eps = m.outlier_weight;
  const bool outliers = eps > 0.0;
  const double log_outlier = outliers ? std::log(eps) + log_outlier_density : kMinusInfinity;
  const double log_inlier = std::log1p(-eps);
  const int weight_states = m.weight_states();
  Eigen::MatrixXd log_prior(weight_states, modes);
  for (int b = 0; b < weight_states; ++b) {
    for (int i = 0; i < modes; ++i) {
      log_prior(b, i) = log_of(m.weight(m.state(b, 0), i)) + log_inlier;
    }
  }
  auto joint = log_joint.array();
  if (weight_states == 1) {
    joint.rowwise() += log_prior.row(0).array();
  } else {
    for (Eigen::Index k = 0; k < k_count; ++k) {
      joint.row(k) += log_prior.row(state[k] / m.variance_states()).array();
    }
  }
  Eigen::ArrayXd top = joint.col(0);
  for (int i = 1; i < modes; ++i) top = top.max(joint.col(i));
  if (outliers) top = top.max(log_outlier);
  Eigen::ArrayXd sum = Eigen::ArrayXd::Zero(k_count);
  for (int i = 0; i < modes; ++i) {
    joint.col(i) -= top;
    exp_in_place(joint.col(i));
    sum += joint.col(i);
  }
  if (outliers) {
    out.outlier = (log_outlier - top).matrix();
    exp_in_place(out.outlier);
    sum += out.outlier.array();
  } else {
    out.outlier = Eigen::VectorXd::Zero(k_count);
  }
  Eigen::ArrayXd range_log_likelihood = sum;
  log_in_place(range_log_likelihood);
  range_log_likelihood += top;
  const Eigen::ArrayXd inverse = sum.inverse();
  joint.colwise() *= inverse;
  if (outliers) out.outlier.array() *= inverse;
  if (per_range) *per_range = range_log_likelihood.matrix();
  out.mode = std::move(log_joint);
  out.transitions.resize(0, 0);
  return range_log_likelihood.sum();
}

// Mode persistence: the scaled forward-backward recursion (Rabiner 1989) over the chain. The
// forward pass's scales are the one-step predictive likelihoods (per_range, when asked).
double chain_e_step(const ExtendedMixture& m, Eigen::MatrixXd& log_b, ExtendedResponsibilities& out,
                    Eigen::VectorXd* per_range, bool forward_only) {
  const Eigen::Index k_count = log_b.rows();
  const int modes = m.modes.modes();
  const Eigen::MatrixXd& a = m.transition;
  // b_k scaled by its largest mode, on arrays over all ranges.
  Eigen::ArrayXd top = log_b.col(0).array();
  for (int i = 1; i < modes; ++i) top = top.max(log_b.col(i).array());
  for (int i = 0; i < modes; ++i) {
    log_b.col(i).array() -= top;
    exp_in_place(log_b.col(i));
  }
  const Eigen::VectorXd shift = top.matrix();
  Eigen::MatrixXd alpha(k_count, modes);
  Eigen::VectorXd scale(k_count);
  double log_likelihood = 0.0;
  for (Eigen::Index k = 0; k < k_count; ++k) {
    const Eigen::RowVectorXd prior = k == 0 ? Eigen::RowVectorXd(m.modes.weight.transpose())
                                            : Eigen::RowVectorXd(alpha.row(k - 1) * a);
    alpha.row(k) = prior.cwiseProduct(log_b.row(k));
    scale[k] = alpha.row(k).sum();
    if (!(scale[k] > 0.0)) {
      throw NumericalError(
          "mode chain E-step: a range has zero probability under every mode the chain allows");
    }
    alpha.row(k) /= scale[k];
    const double range_log_likelihood = std::log(scale[k]) + shift[k];
    if (per_range) (*per_range)[k] = range_log_likelihood;
    log_likelihood += range_log_likelihood;
  }
  out.outlier = Eigen::VectorXd::Zero(k_count);
  if (forward_only) return log_likelihood;
  Eigen::MatrixXd beta(k_count, modes);
  beta.row(k_count - 1).setOnes();
  out.transitions = Eigen::MatrixXd::Zero(modes, modes);
  for (Eigen::Index k = k_count - 1; k > 0; --k) {
    const Eigen::RowVectorXd next = log_b.row(k).cwiseProduct(beta.row(k)) / scale[k];
    out.transitions.noalias() += (alpha.row(k - 1).transpose() * next).cwiseProduct(a);
    beta.row(k - 1) = (a * next.transpose()).transpose();
  }
  out.mode = alpha.cwiseProduct(beta);
  out.mode.array().colwise() /= out.mode.rowwise().sum().array();
  return log_likelihood;
}

void validate_e_step_arguments(const Eigen::Ref<const Eigen::VectorXd>& residual,
                               const Eigen::Ref<const Eigen::VectorXi>& state,
                               const Eigen::Ref<const Eigen::MatrixXd>& mode_shift,
                               const ExtendedMixture& model) {
  require_same_length(residual.size(), "residual", state.size(), "noise states");
  if (residual.size() == 0) throw InvalidInput("the E-step needs at least one range");
  if (state.minCoeff() < 0 || state.maxCoeff() >= model.states()) {
    throw InvalidInput("a noise state is out of range");
  }
  if (mode_shift.size() > 0 &&
      (mode_shift.rows() != residual.size() || mode_shift.cols() != model.modes.modes())) {
    throw InvalidInput("the mode shifts must be one row per range and one column per mode");
  }
}

// The E-step's common part: emissions, then independent draws or the chain.
double e_step(const Eigen::Ref<const Eigen::VectorXd>& residual,
              const Eigen::Ref<const Eigen::VectorXi>& state,
              const Eigen::Ref<const Eigen::MatrixXd>& mode_shift, const ExtendedMixture& model,
              double resolution, ExtendedResponsibilities& out, Eigen::VectorXd* per_range,
              bool forward_only) {
  Eigen::MatrixXd log_b;
  log_emission(residual, state, mode_shift, model, resolution, log_b);
  const double log_outlier_density =
      model.outlier_weight > 0.0
          ? std::log(model.outlier_density) + (resolution > 0.0 ? std::log(resolution) : 0.0)
          : 0.0;
  const double log_likelihood =
      model.transition.size() > 0
          ? chain_e_step(model, log_b, out, per_range, forward_only)
          : independent_e_step(state, model, log_outlier_density, log_b, out, per_range);
  if (!std::isfinite(log_likelihood)) {
    throw NumericalError("extended mixture log-likelihood is not finite");
  }
  return log_likelihood;
}

}  // namespace

void NoiseBins::refresh_table() {
  if (!term.is_parametric_noise()) return;
  const Eigen::VectorXd f = noise_level_values(term);
  const Eigen::Index modes = intercept.size();
  table.resize(f.size(), modes);
  for (Eigen::Index l = 0; l < f.size(); ++l) {
    const Eigen::ArrayXd eta = intercept.array() + slope.array() * f[l];
    if (term.parameter == Parameter::Weights) {
      const Eigen::ArrayXd e = (eta - eta.maxCoeff()).exp();
      table.row(l) = (e / e.sum()).matrix().transpose();
    } else {
      table.row(l) = eta.exp().matrix().transpose();
    }
  }
}

double ExtendedMixture::weight(int state, int mode) const {
  return weight_bins ? weight_bins->table(state / variance_states(), mode) : modes.weight[mode];
}

double ExtendedMixture::variance(int state, int mode) const {
  return variance_bins ? variance_bins->table(state % variance_states(), mode)
                       : modes.variance[mode];
}

void ExtendedMixture::validate() const {
  modes.validate();
  const int m = modes.modes();
  if (weight_bins) {
    validate_bins(*weight_bins, Parameter::Weights, m, "binned weights");
    require_stochastic_rows(weight_bins->table, "binned weights");
  }
  if (variance_bins) {
    validate_bins(*variance_bins, Parameter::Spread, m, "binned variances");
    require_finite(variance_bins->table, "binned variances");
    if (!(variance_bins->table.array() > 0.0).all()) {
      throw InvalidInput("binned variances must be positive");
    }
  }
  if (transition.size() > 0) {
    require_shape(transition, m, m, "mode transition matrix");
    require_stochastic_rows(transition, "mode transition matrix");
    if (weight_bins || outlier_weight > 0.0) {
      throw InvalidInput(
          "a mode transition matrix cannot be combined with binned weights or an outlier "
          "component");
    }
  }
  if (!(outlier_weight >= 0.0 && outlier_weight < 1.0)) {
    throw InvalidInput("outlier weight must be in [0, 1)");
  }
  if (outlier_weight > 0.0 && !(outlier_density > 0.0 && std::isfinite(outlier_density))) {
    throw InvalidInput("outlier density must be positive and finite");
  }
}

ExtendedMixture without_extensions(const MixtureParameters& modes) {
  ExtendedMixture out;
  out.modes = modes;
  return out;
}

double extended_e_step(const Eigen::Ref<const Eigen::VectorXd>& residual,
                       const Eigen::Ref<const Eigen::VectorXi>& state,
                       const Eigen::Ref<const Eigen::MatrixXd>& mode_shift,
                       const ExtendedMixture& model, ExtendedResponsibilities& out) {
  validate_e_step_arguments(residual, state, mode_shift, model);
  if (!model.has_extension() && mode_shift.size() == 0) {
    out.outlier = Eigen::VectorXd::Zero(residual.size());
    out.transitions.resize(0, 0);
    return mixture_e_step(residual, model.modes, out.mode);  // Eq. 18, Eq. 22
  }
  return e_step(residual, state, mode_shift, model, 0.0, out, nullptr, false);
}

Eigen::VectorXd extended_log_scores(const Eigen::Ref<const Eigen::VectorXd>& residual,
                                    const Eigen::Ref<const Eigen::VectorXi>& state,
                                    const Eigen::Ref<const Eigen::MatrixXd>& mode_shift,
                                    const ExtendedMixture& model, double resolution) {
  validate_e_step_arguments(residual, state, mode_shift, model);
  if (!(resolution >= 0.0)) throw InvalidInput("the ranges' resolution must be non-negative");
  Eigen::VectorXd per_range(residual.size());
  ExtendedResponsibilities scratch;
  e_step(residual, state, mode_shift, model, resolution, scratch, &per_range, true);
  return per_range;
}

int extension_parameters(const ExtendedMixture& model) {
  const int m = model.modes.modes();
  int extra = 0;
  // A parametric term adds one slope per free mode; bins one value per free mode and extra bin.
  const auto added = [](const NoiseBins& b, int free_modes) {
    return b.term.is_parametric_noise() ? free_modes : (b.bins() - 1) * free_modes;
  };
  if (model.weight_bins) extra += added(*model.weight_bins, m - 1);
  if (model.variance_bins) extra += added(*model.variance_bins, m);
  if (model.transition.size() > 0) extra += m * (m - 1);
  if (model.outlier_weight > 0.0) extra += 1;
  return extra;
}

}  // namespace tofcomp::core
