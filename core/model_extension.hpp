// Eq. 8 extended by the terms of the grammar (core/effect_grammar.hpp) that the model search
// kept (calibration/model_search.hpp):
//   y_k = d + H(t^j_k) θ + Σ_t γ_t f_t(c_k) + w_k,
// the sum over the bias terms, and w_k drawn from the extended mixture
// (core/extended_mixture.hpp): a mode-offset term moves its mode by β f(c_k), spread and weight
// terms bin their parameter by a covariate, and the structure may be a Markov chain over the
// modes, one more mode or an outlier component. Every term is linear in its coefficients or
// closed-form in its bins, so training and testing keep the closed forms of §5-§6
// (core/extended_em.hpp). What a calibration file stores next to the paper's model, and what the
// offline tools and the daemon apply.
#pragma once

#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

#include "core/covariate_table.hpp"
#include "core/effect_grammar.hpp"
#include "core/extended_mixture.hpp"

namespace tofcomp::core {

// A fitted bias or mode-offset term: its coefficients, one per design column.
struct MeanTermFit {
  Term term;
  Eigen::VectorXd coefficients;
};

// The covariates at one instant, as the daemon has them scan by scan; the junction's lag for each
// time constant the calibration's terms use (ModelExtension::lag_time_constants()).
struct CovariatesAt {
  double junction_c = 0.0;
  double heating_rate_c_per_min = 0.0;
  double time_since_power_on_s = 0.0;
  double time_h = 0.0;
  double ambient_c = 0.0;
  std::vector<std::pair<double, double>> junction_lag_c;  // (τ, L_τ(t^j) − t^j)
};

struct ModelExtension {
  std::vector<EffectLabel> effects;  // what the search added, in that order
  std::vector<MeanTermFit> mean_terms;
  ExtendedMixture extended_mixture;  // replaces the paper's mixture (model.mixture)

  // Throws InvalidInput when a term or the mixture is invalid, a mode-offset term names a mode
  // the mixture lacks, or a coefficient is not finite.
  void validate() const;
  bool has_mode_shift() const;
  // At every range of a covariate table: Σ_t γ_t f_t(c_k) over the bias terms; each mode's offset
  // shift (K × M, empty without mode-offset terms); the noise state of the extended mixture.
  Eigen::VectorXd bias(const CovariateTable& covariates) const;
  Eigen::MatrixXd mode_shift(const CovariateTable& covariates) const;
  Eigen::VectorXi states(const CovariateTable& covariates) const;
  // The same at one instant.
  double bias_at(const CovariatesAt& at) const;
  Eigen::VectorXd mode_shift_at(const CovariatesAt& at) const;  // M entries (zeros without)
  int state_at(const CovariatesAt& at) const;
  // The time constants of the junction lags the terms read.
  std::vector<double> lag_time_constants() const;
  // The effects' names for people, in the order added: "warm-up after power-on, outliers".
  std::string name() const;
};

// The covariate of a term at one instant. Throws InvalidInput for a lag whose τ `at` lacks.
double covariate_at(const CovariatesAt& at, Covariate covariate, double time_constant_s);

// The noise state of each range under an extended mixture's bins.
Eigen::VectorXi noise_states(const ExtendedMixture& mixture, const CovariateTable& covariates);

}  // namespace tofcomp::core
