#include "core/model_extension.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/validation.hpp"

namespace tofcomp::core {
namespace {

// Lags are matched by τ to this relative tolerance (a file round trip may round τ).
constexpr double kLagTimeConstantTolerance = 1e-9;

}  // namespace

void ModelExtension::validate() const {
  extended_mixture.validate();
  for (const MeanTermFit& t : mean_terms) {
    t.term.validate();
    if (!t.term.is_mean_term()) {
      throw InvalidInput("term " + t.term.describe() + " is not a bias or mode-offset term");
    }
    if (t.coefficients.size() != t.term.columns()) {
      throw InvalidInput("term " + t.term.describe() + " has " +
                         std::to_string(t.coefficients.size()) + " coefficients for " +
                         std::to_string(t.term.columns()) + " columns");
    }
    require_finite(t.coefficients, "term coefficients");
    if (t.term.parameter == Parameter::ModeOffset &&
        t.term.mode >= extended_mixture.modes.modes()) {
      throw InvalidInput("term " + t.term.describe() + " names a mode the mixture lacks");
    }
  }
}

bool ModelExtension::has_mode_shift() const {
  return std::any_of(mean_terms.begin(), mean_terms.end(), [](const MeanTermFit& t) {
    return t.term.parameter == Parameter::ModeOffset;
  });
}

Eigen::VectorXd ModelExtension::bias(const CovariateTable& covariates) const {
  Eigen::VectorXd out = Eigen::VectorXd::Zero(covariates.size());
  for (const MeanTermFit& t : mean_terms) {
    if (t.term.parameter == Parameter::Bias) out += covariates.columns(t.term) * t.coefficients;
  }
  return out;
}

Eigen::MatrixXd ModelExtension::mode_shift(const CovariateTable& covariates) const {
  if (!has_mode_shift()) return Eigen::MatrixXd(0, 0);
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(covariates.size(), extended_mixture.modes.modes());
  for (const MeanTermFit& t : mean_terms) {
    if (t.term.parameter == Parameter::ModeOffset) {
      out.col(t.term.mode) += covariates.columns(t.term) * t.coefficients;
    }
  }
  return out;
}

Eigen::VectorXi ModelExtension::states(const CovariateTable& covariates) const {
  return noise_states(extended_mixture, covariates);
}

double covariate_at(const CovariatesAt& at, Covariate covariate, double time_constant_s) {
  switch (covariate) {
    case Covariate::JunctionTemperature:
      return at.junction_c;
    case Covariate::HeatingRate:
      return at.heating_rate_c_per_min;
    case Covariate::TimeSincePowerOn:
      return at.time_since_power_on_s;
    case Covariate::Time:
      return at.time_h;
    case Covariate::Ambient:
      return at.ambient_c;
    case Covariate::JunctionLag:
      for (const auto& [tau, lag] : at.junction_lag_c) {
        if (std::abs(tau - time_constant_s) <= kLagTimeConstantTolerance * time_constant_s) {
          return lag;
        }
      }
      throw InvalidInput("no junction lag of time constant " + std::to_string(time_constant_s) +
                         " s at this instant");
    case Covariate::None:
      break;
  }
  throw InvalidInput("no covariate");
}

double ModelExtension::bias_at(const CovariatesAt& at) const {
  double out = 0.0;
  for (const MeanTermFit& t : mean_terms) {
    if (t.term.parameter != Parameter::Bias) continue;
    Eigen::RowVectorXd row(t.term.columns());
    term_design_row(t.term, covariate_at(at, t.term.covariate, t.term.time_constant_s), row);
    out += row.dot(t.coefficients);
  }
  return out;
}

Eigen::VectorXd ModelExtension::mode_shift_at(const CovariatesAt& at) const {
  Eigen::VectorXd out = Eigen::VectorXd::Zero(extended_mixture.modes.modes());
  for (const MeanTermFit& t : mean_terms) {
    if (t.term.parameter != Parameter::ModeOffset) continue;
    Eigen::RowVectorXd row(t.term.columns());
    term_design_row(t.term, covariate_at(at, t.term.covariate, t.term.time_constant_s), row);
    out[t.term.mode] += row.dot(t.coefficients);
  }
  return out;
}

int ModelExtension::state_at(const CovariatesAt& at) const {
  const ExtendedMixture& m = extended_mixture;
  const int weight_bin =
      m.weight_bins ? term_bin(m.weight_bins->term,
                               covariate_at(at, m.weight_bins->term.covariate,
                                            m.weight_bins->term.time_constant_s))
                    : 0;
  const int variance_bin =
      m.variance_bins ? term_bin(m.variance_bins->term,
                                 covariate_at(at, m.variance_bins->term.covariate,
                                              m.variance_bins->term.time_constant_s))
                      : 0;
  return m.state(weight_bin, variance_bin);
}

std::vector<double> ModelExtension::lag_time_constants() const {
  std::vector<double> out;
  const auto consider = [&](const Term& term) {
    if (term.covariate == Covariate::JunctionLag) out.push_back(term.time_constant_s);
  };
  for (const MeanTermFit& t : mean_terms) consider(t.term);
  if (extended_mixture.weight_bins) consider(extended_mixture.weight_bins->term);
  if (extended_mixture.variance_bins) consider(extended_mixture.variance_bins->term);
  return out;
}

std::string ModelExtension::name() const {
  std::string out;
  for (const EffectLabel& e : effects) out += (out.empty() ? "" : ", ") + effect_name(e);
  return out;
}

Eigen::VectorXi noise_states(const ExtendedMixture& mixture, const CovariateTable& covariates) {
  const Eigen::Index n = covariates.size();
  const Eigen::VectorXi weight_bin = mixture.weight_bins ? covariates.bins(mixture.weight_bins->term)
                                                         : Eigen::VectorXi(Eigen::VectorXi::Zero(n));
  const Eigen::VectorXi variance_bin = mixture.variance_bins
                                           ? covariates.bins(mixture.variance_bins->term)
                                           : Eigen::VectorXi(Eigen::VectorXi::Zero(n));
  return weight_bin * mixture.variance_states() + variance_bin;
}

}  // namespace tofcomp::core
