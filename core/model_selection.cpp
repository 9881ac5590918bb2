#include "core/model_selection.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include "core/error.hpp"
#include "core/validation.hpp"

namespace tofcomp::core {
namespace {

// Rows of the alternate held-out blocks (odd = true) or of the training blocks.
std::vector<Eigen::Index> block_rows(Eigen::Index k, Eigen::Index block, bool odd) {
  std::vector<Eigen::Index> rows;
  for (Eigen::Index i = 0; i < k; ++i) {
    if (((i / block) % 2 == 1) == odd) rows.push_back(i);
  }
  return rows;
}

CandidateScore score_candidate(const Basis& basis, const Eigen::VectorXd& temperature,
                               const Eigen::VectorXd& y, double null_ll,
                               const SelectionOptions& options) {
  CandidateScore score;
  score.name = basis.describe();
  score.columns = basis.columns();
  score.parameters = basis.columns() + 3 * options.em.modes - 1;
  try {
    const Eigen::MatrixXd h = basis.design_matrix(temperature);
    const EmTrainResult fit = train_em(h, y, options.em);
    const Eigen::VectorXd residual = y - h * fit.theta;
    score.converged = fit.converged;
    score.log_likelihood = fit.log_likelihood;
    score.glr = 2.0 * (fit.log_likelihood - null_ll);
    score.paper_eq29 = null_ll / fit.log_likelihood;
    score.paper_eq25 = paper_eq25_statistic(residual, fit.responsibilities, fit.mixture);
    score.bic =
        -2.0 * fit.log_likelihood + score.parameters * std::log(static_cast<double>(y.size()));

    const auto train_rows = block_rows(y.size(), options.held_out_block, false);
    const auto test_rows = block_rows(y.size(), options.held_out_block, true);
    const Eigen::MatrixXd h_train = h(train_rows, Eigen::all);
    const EmTrainResult held = train_em(h_train, y(train_rows), options.em);
    const Eigen::VectorXd test_residual = y(test_rows) - h(test_rows, Eigen::all) * held.theta;
    score.held_out_log_likelihood =
        mixture_log_likelihood(test_residual, held.mixture) / static_cast<double>(test_rows.size());
    score.ok = true;
  } catch (const Error& e) {
    score.ok = false;
    score.error = e.what();
  }
  return score;
}

template <typename Better>
int best_index(const std::vector<CandidateScore>& scores, Better better) {
  int best = -1;
  for (int i = 0; i < static_cast<int>(scores.size()); ++i) {
    if (!scores[static_cast<std::size_t>(i)].ok) continue;
    if (best < 0 ||
        better(scores[static_cast<std::size_t>(i)], scores[static_cast<std::size_t>(best)])) {
      best = i;
    }
  }
  return best;
}

}  // namespace

double single_gaussian_log_likelihood(const Eigen::Ref<const Eigen::VectorXd>& values) {
  const double k = static_cast<double>(values.size());
  const double variance = (values.array() - values.mean()).square().sum() / k;
  if (!(variance > 0.0)) {
    throw NumericalError(
        "the single-Gaussian null hypothesis (Eq. 28) needs data with non-zero "
        "variance");
  }
  return -0.5 * k * (std::log(2.0 * std::numbers::pi * variance) + 1.0);
}

double paper_eq25_statistic(const Eigen::Ref<const Eigen::VectorXd>& residual,
                            const Eigen::MatrixXd& responsibilities,
                            const MixtureParameters& mixture) {
  double total = 0.0;
  for (int i = 0; i < mixture.modes(); ++i) {
    const auto r = responsibilities.col(i);
    total += std::log(mixture.variance[i]) * r.sum();
    total +=
        r.dot((residual.array() - mixture.mean[i]).square().matrix()) / (2.0 * mixture.variance[i]);
  }
  return total;
}

SelectionResult select_model(const std::vector<Basis>& candidates,
                             const Eigen::Ref<const Eigen::VectorXd>& junction_temperature_c,
                             const Eigen::Ref<const Eigen::VectorXd>& y_minus_d,
                             const SelectionOptions& options) {
  require_same_length(junction_temperature_c.size(), "junction temperature", y_minus_d.size(),
                      "y - d");
  require_finite(junction_temperature_c, "junction temperature");
  require_finite(y_minus_d, "y - d");
  if (candidates.empty()) throw InvalidInput("model selection needs at least one candidate basis");
  if (options.held_out_block < 1) throw InvalidInput("held_out_block must be at least 1");
  if (y_minus_d.size() < 4 * options.held_out_block) {
    throw InvalidInput("model selection needs at least four held-out blocks of samples");
  }

  const Eigen::VectorXd temperature = junction_temperature_c;
  const Eigen::VectorXd y = y_minus_d;
  SelectionResult result;
  result.null_log_likelihood = single_gaussian_log_likelihood(y);
  for (const auto& basis : candidates) {
    result.scores.push_back(
        score_candidate(basis, temperature, y, result.null_log_likelihood, options));
  }
  result.best_by_glr =
      best_index(result.scores, [](const auto& a, const auto& b) { return a.glr > b.glr; });
  result.best_by_bic =
      best_index(result.scores, [](const auto& a, const auto& b) { return a.bic < b.bic; });
  result.best_by_held_out = best_index(result.scores, [](const auto& a, const auto& b) {
    return a.held_out_log_likelihood > b.held_out_log_likelihood;
  });
  return result;
}

}  // namespace tofcomp::core
