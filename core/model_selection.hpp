// §7: choosing H(.) among candidate bases (Algorithm 2, Eq. 25-29), and beside it criteria
// that over-fitting cannot fool.
//
// For each candidate basis the model is trained by EM (§5) and scored by:
//   log_likelihood  ℓ_i, the maximized mixture log-likelihood of y − d (Eq. 27);
//   glr             2(ℓ_i − ℓ_0) against the single-Gaussian null H_0: y − d ~ N(m, σ²)
//                   (Eq. 28; the standard generalized likelihood ratio statistic);
//   paper_eq29      Λ_i = ℓ_0 / ℓ_i, Eq. 29 as printed (a ratio of log-likelihoods);
//   paper_eq25      Eq. 25 as printed: Σ_i [log(σ_i²) 1ᵀΣ_i1 + (2σ_i²)⁻¹ eᵢᵀ Σ_i eᵢ]. It is,
//                   up to constants and a factor ½ on its log terms, the negated expected
//                   complete-data log-likelihood, so a better fit makes it smaller, although
//                   Algorithm 2 says to select its maximum;
//   bic             −2ℓ_i + n_i log K, n_i = p + 3M − 1 free parameters;
//   held_out        the mean log-likelihood per sample on alternate blocks of samples held out
//                   of training (the model is trained on the other blocks).
// GLR (like Eq. 25) always favours the larger of nested bases; BIC and held-out likelihood
// do not, and are the criteria to trust on noisy data.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/basis.hpp"
#include "core/em_train.hpp"

namespace tofcomp::core {

struct SelectionOptions {
  EmTrainOptions em;
  // Samples are split into consecutive blocks of this length; odd blocks are held out.
  Eigen::Index held_out_block = 100;
};

struct CandidateScore {
  std::string name;
  int columns = 0;
  int parameters = 0;
  bool ok = false;  // false: training failed, `error` says why, the scores are not set
  std::string error;
  bool converged = false;
  double log_likelihood = 0.0;
  double glr = 0.0;
  double paper_eq25 = 0.0;
  double paper_eq29 = 0.0;
  double bic = 0.0;
  double held_out_log_likelihood = 0.0;  // per held-out sample
};

struct SelectionResult {
  double null_log_likelihood = 0.0;  // ℓ_0 of Eq. 28
  std::vector<CandidateScore> scores;
  // Indices into scores; −1 when no candidate could be trained.
  int best_by_glr = -1;
  int best_by_bic = -1;
  int best_by_held_out = -1;
};

// Algorithm 2 over the candidates on junction temperatures t̂^j and y − d. A candidate whose
// training fails (e.g. a singular HᵀC⁻¹H) is reported with its error and skipped, not fatal;
// invalid arguments throw InvalidInput.
SelectionResult select_model(const std::vector<Basis>& candidates,
                             const Eigen::Ref<const Eigen::VectorXd>& junction_temperature_c,
                             const Eigen::Ref<const Eigen::VectorXd>& y_minus_d,
                             const SelectionOptions& options = {});

// ℓ_0 of Eq. 28: the maximized log-likelihood of a single Gaussian.
double single_gaussian_log_likelihood(const Eigen::Ref<const Eigen::VectorXd>& values);

// Eq. 25 as printed, for trained responsibilities r (K × M) and residuals e = y − d − Hθ.
double paper_eq25_statistic(const Eigen::Ref<const Eigen::VectorXd>& residual,
                            const Eigen::MatrixXd& responsibilities,
                            const MixtureParameters& mixture);

}  // namespace tofcomp::core
