#include "core/extended_mixture.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include "core/error.hpp"
#include "core/validation.hpp"

namespace tofcomp::core {
namespace {

constexpr double kRowSumTolerance = 1e-9;

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

// log N(e; μ_i, σ²_{b,i}) for every range (rows) and mode (columns), without the prior.
void log_emission(const Eigen::Ref<const Eigen::VectorXd>& e,
                  const Eigen::Ref<const Eigen::VectorXi>& bin, const ExtendedMixture& m,
                  Eigen::MatrixXd& out) {
  const int modes = m.modes.modes();
  out.resize(e.size(), modes);
  for (Eigen::Index k = 0; k < e.size(); ++k) {
    for (int i = 0; i < modes; ++i) {
      const double variance = m.variance(bin[k], i);
      const double centred = e[k] - m.modes.mean[i];
      out(k, i) =
          -0.5 * std::log(2.0 * std::numbers::pi * variance) - centred * centred / (2.0 * variance);
    }
  }
}

double log_of(double p) {
  return p > 0.0 ? std::log(p) : -std::numeric_limits<double>::infinity();
}

// Independent draws (with bin weights and the outlier component): a log-sum-exp per range.
double independent_e_step(const Eigen::Ref<const Eigen::VectorXi>& bin, const ExtendedMixture& m,
                          Eigen::MatrixXd& log_joint, ExtendedResponsibilities& out) {
  const Eigen::Index k_count = log_joint.rows();
  const int modes = m.modes.modes();
  const double eps = m.outlier_weight;
  const double log_outlier =
      eps > 0.0 ? std::log(eps * m.outlier_density) : -std::numeric_limits<double>::infinity();
  const double log_inlier = std::log1p(-eps);
  out.outlier = Eigen::VectorXd::Zero(k_count);
  double log_likelihood = 0.0;
  for (Eigen::Index k = 0; k < k_count; ++k) {
    double top = log_outlier;
    for (int i = 0; i < modes; ++i) {
      log_joint(k, i) += log_of(m.weight(bin[k], i)) + log_inlier;
      top = std::max(top, log_joint(k, i));
    }
    double sum = 0.0;
    for (int i = 0; i < modes; ++i) {
      log_joint(k, i) = std::exp(log_joint(k, i) - top);
      sum += log_joint(k, i);
    }
    const double outlier = std::exp(log_outlier - top);
    sum += outlier;
    log_joint.row(k) /= sum;
    out.outlier[k] = outlier / sum;
    log_likelihood += top + std::log(sum);
  }
  out.mode = std::move(log_joint);
  out.transitions.resize(0, 0);
  return log_likelihood;
}

// Mode persistence: the scaled forward-backward recursion (Rabiner 1989) over the chain.
double chain_e_step(const ExtendedMixture& m, Eigen::MatrixXd& log_b,
                    ExtendedResponsibilities& out) {
  const Eigen::Index k_count = log_b.rows();
  const int modes = m.modes.modes();
  const Eigen::MatrixXd& a = m.transition;
  Eigen::VectorXd shift(k_count);
  for (Eigen::Index k = 0; k < k_count; ++k) {
    shift[k] = log_b.row(k).maxCoeff();
    log_b.row(k) = (log_b.row(k).array() - shift[k]).exp().matrix();  // b_k, scaled
  }
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
    log_likelihood += std::log(scale[k]) + shift[k];
  }
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
  out.outlier = Eigen::VectorXd::Zero(k_count);
  return log_likelihood;
}

}  // namespace

Eigen::VectorXi ExtendedMixture::bin_of(const Eigen::Ref<const Eigen::VectorXd>& junction_c) const {
  Eigen::VectorXi out(junction_c.size());
  for (Eigen::Index k = 0; k < junction_c.size(); ++k) {
    int b = 0;
    while (b < bin_edges_c.size() && junction_c[k] >= bin_edges_c[b]) ++b;
    out[k] = b;
  }
  return out;
}

double ExtendedMixture::weight(int bin, int mode) const {
  return bin_weight.size() > 0 ? bin_weight(bin, mode) : modes.weight[mode];
}

double ExtendedMixture::variance(int bin, int mode) const {
  return bin_variance.size() > 0 ? bin_variance(bin, mode) : modes.variance[mode];
}

void ExtendedMixture::validate() const {
  modes.validate();
  const int m = modes.modes();
  require_finite(bin_edges_c, "temperature bin edges");
  for (Eigen::Index b = 1; b < bin_edges_c.size(); ++b) {
    if (!(bin_edges_c[b] > bin_edges_c[b - 1])) {
      throw InvalidInput("temperature bin edges must increase strictly");
    }
  }
  if (bin_weight.size() > 0) {
    require_shape(bin_weight, bins(), m, "bin weights");
    require_stochastic_rows(bin_weight, "bin weights");
  }
  if (bin_variance.size() > 0) {
    require_shape(bin_variance, bins(), m, "bin variances");
    require_finite(bin_variance, "bin variances");
    if (!(bin_variance.array() > 0.0).all()) throw InvalidInput("bin variances must be positive");
  }
  if (transition.size() > 0) {
    require_shape(transition, m, m, "mode transition matrix");
    require_stochastic_rows(transition, "mode transition matrix");
    if (bin_weight.size() > 0 || outlier_weight > 0.0) {
      throw InvalidInput(
          "a mode transition matrix cannot be combined with temperature-dependent weights or an "
          "outlier component");
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
                       const Eigen::Ref<const Eigen::VectorXi>& bin, const ExtendedMixture& model,
                       ExtendedResponsibilities& out) {
  require_same_length(residual.size(), "residual", bin.size(), "temperature bins");
  if (residual.size() == 0) throw InvalidInput("the E-step needs at least one range");
  if (bin.size() > 0 && (bin.minCoeff() < 0 || bin.maxCoeff() >= model.bins())) {
    throw InvalidInput("a temperature bin index is out of range");
  }
  if (!model.has_extension()) {
    out.outlier = Eigen::VectorXd::Zero(residual.size());
    out.transitions.resize(0, 0);
    return mixture_e_step(residual, model.modes, out.mode);  // Eq. 18, Eq. 22
  }
  Eigen::MatrixXd log_b;
  log_emission(residual, bin, model, log_b);
  const double log_likelihood = model.transition.size() > 0
                                    ? chain_e_step(model, log_b, out)
                                    : independent_e_step(bin, model, log_b, out);
  if (!std::isfinite(log_likelihood)) {
    throw NumericalError("extended mixture log-likelihood is not finite");
  }
  return log_likelihood;
}

int extension_parameters(const ExtendedMixture& model) {
  const int m = model.modes.modes();
  int extra = 0;
  if (model.bin_weight.size() > 0) extra += (model.bins() - 1) * (m - 1);
  if (model.bin_variance.size() > 0) extra += (model.bins() - 1) * m;
  if (model.transition.size() > 0) extra += m * (m - 1);
  if (model.outlier_weight > 0.0) extra += 1;
  return extra;
}

}  // namespace tofcomp::core
