#include "core/structure_search.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <tuple>

#include "core/error.hpp"
#include "core/measurement_model.hpp"  // TemperatureRange
#include "core/model_selection.hpp"
#include "core/validation.hpp"

namespace tofcomp::core {
namespace {

constexpr int kPaperModes = 2;
// A fold smaller than this is too small to score a candidate on.
constexpr Eigen::Index kMinimumRangesPerFold = 20;
// A fold gets at least this many blocks: on a short record the blocks shrink to keep it.
constexpr Eigen::Index kMinimumBlocksPerFold = 10;
// The search's EM stopping rule: loose enough to be quick, tight enough that the held-out
// log-likelihoods it compares (differences of ~1e-4 per range matter) have settled.
constexpr double kSearchLogLikelihoodTolerance = 1e-8;
// A fold's fit that starts from the same fold's fit of the order below is stopped at this
// looser rule: it is only scored, and its start was fitted to the other folds alone, so stopping
// earlier leaves it nearer a start that is no better on the held-out ranges. A fold's fit that
// starts from the whole fit (which saw the held-out ranges) keeps the search's rule: stopped
// early it would keep some of that fit to the held-out ranges, and favour candidates with more
// parameters (tried: at 1e-7 everywhere, 3 of 64 blind-draw runs took one more mode).
constexpr double kFoldLogLikelihoodTolerance = 1e-7;
constexpr double kSearchWeightTolerance = 1e-4;
constexpr int kSearchMaxIterations = 2000;

constexpr const char* kPolynomial = "polynomial";
constexpr const char* kFourier = "fourier";
constexpr const char* kGiven = "given";

class Search {
 public:
  Search(const Eigen::VectorXd& temperature, const Eigen::VectorXd& y,
         const StructureSearchOptions& options, const SearchProgress& progress)
      : temperature_(temperature),
        y_(y),
        options_(options),
        progress_(progress),
        scaling_(TemperatureScaling::spanning(temperature)),
        block_(std::clamp(y.size() / (options.folds * kMinimumBlocksPerFold), Eigen::Index{1},
                          options.block)) {
    const double span = temperature.maxCoeff() - temperature.minCoeff();
    fourier_f0_per_c_ = 1.0 / (2.0 * std::max(span, 2.0 * scaling_.half_range_c));
    // Each fold's training rows, and its held-out rows inside the temperatures they span.
    train_rows_.resize(static_cast<std::size_t>(options.folds));
    held_rows_.resize(static_cast<std::size_t>(options.folds));
    for (Eigen::Index k = 0; k < y.size(); ++k) {
      const auto fold = static_cast<std::size_t>((k / block_) % options.folds);
      for (std::size_t f = 0; f < train_rows_.size(); ++f) {
        if (f != fold) train_rows_[f].push_back(k);
      }
    }
    for (std::size_t f = 0; f < held_rows_.size(); ++f) {
      const Eigen::VectorXd train_t = temperature(train_rows_[f]);
      const TemperatureRange trained{train_t.minCoeff(), train_t.maxCoeff()};
      for (Eigen::Index k = 0; k < y.size(); ++k) {
        const auto fold = static_cast<std::size_t>((k / block_) % options.folds);
        if (fold == f && trained.contains(temperature[k])) held_rows_[f].push_back(k);
      }
      held_out_count_ += static_cast<Eigen::Index>(held_rows_[f].size());
      for (const Eigen::Index k : held_rows_[f]) {
        block_slot_.emplace(k / block_, block_slot_.size());
      }
    }
  }

  Basis basis_of(const std::string& family, int order) const {
    if (family == kGiven) return *options_.basis;
    if (family == kFourier) return Basis::fourier(order, fourier_f0_per_c_);
    return Basis({BasisTerm{BasisKind::Polynomial, order, PolynomialForm::Legendre, 0.0}},
                 scaling_);
  }

  // Trains and scores (family, order, modes) once; later calls return the same index.
  // `warm`: where the whole fit starts; `fold_warm`: where each fold's fit starts (empty: at the
  // whole fit).
  int visit(const std::string& family, int order, int modes,
            const std::optional<EmStartingPoint>& warm,
            const std::vector<EmStartingPoint>& fold_warm = {}) {
    const auto key = std::make_tuple(family, order, modes);
    if (const auto found = index_.find(key); found != index_.end()) return found->second;
    CandidateEvidence e;
    e.family = family;
    e.order = order;
    e.modes = modes;
    const Basis basis = basis_of(family, order);
    e.name = basis.describe() + ", " + std::to_string(modes) + (modes == 1 ? " mode" : " modes");
    e.parameters = basis.columns() + 3 * modes - 1;
    EmTrainResult fit;
    std::vector<EmStartingPoint> fold_fits;
    try {
      const Eigen::MatrixXd h = basis.design_matrix(temperature_);
      EmTrainOptions em = options_.em;
      em.modes = modes;
      em.start = warm;
      fit = train_em(h, y_, em);
      e.log_likelihood = fit.log_likelihood;
      e.glr = 2.0 * (fit.log_likelihood - null_log_likelihood());
      e.bic = -2.0 * fit.log_likelihood +
              e.parameters * std::log(static_cast<double>(y_.size()));
      e.block_log_likelihood = score_held_out_blocks(h, fit, em, fold_warm, fold_fits);
      e.held_out_log_likelihood =
          e.block_log_likelihood.sum() / static_cast<double>(held_out_count_);
      e.ok = true;
    } catch (const Error& error) {
      e.ok = false;
      e.error = error.what();
    }
    evidence_.push_back(e);
    fits_.push_back(std::move(fit));
    fold_fits_.push_back(std::move(fold_fits));
    const int index = static_cast<int>(evidence_.size()) - 1;
    index_[key] = index;
    if (progress_) progress_(e);
    return index;
  }

  double score(int index) const {
    if (index < 0) return -std::numeric_limits<double>::infinity();
    const CandidateEvidence& e = evidence_[static_cast<std::size_t>(index)];
    return e.ok ? e.held_out_log_likelihood : -std::numeric_limits<double>::infinity();
  }

  // Orders 1, 2, … of one family at M modes, each warm-started from the one below, until
  // `patience` orders in a row fail to beat the best. Returns the best index (−1: none trained).
  int scan_orders(const std::string& family, int modes, int max_order) {
    int best = -1;
    int since_best = 0;
    std::optional<EmStartingPoint> warm;
    std::vector<EmStartingPoint> fold_warm;
    for (int order = 1; order <= max_order && since_best < options_.patience; ++order) {
      const int index = visit(family, order, modes, warm, fold_warm);
      const CandidateEvidence& e = evidence_[static_cast<std::size_t>(index)];
      if (e.ok) {
        const EmTrainResult& fit = fits_[static_cast<std::size_t>(index)];
        warm = EmStartingPoint{fit.theta, fit.mixture};
        fold_warm = fold_fits_[static_cast<std::size_t>(index)];
      }
      if (e.ok && (best < 0 || score(index) > score(best))) {
        best = index;
        since_best = 0;
      } else {
        ++since_best;
      }
    }
    return best;
  }

  // M = 1 … max_modes at one basis, each from the quantile start.
  int scan_modes(const std::string& family, int order) {
    int best = -1;
    for (int modes = 1; modes <= options_.max_modes; ++modes) {
      const int index = visit(family, order, modes, std::nullopt);
      if (score(index) > score(best)) best = index;
    }
    return best;
  }

  // How far candidate a's held-out log-likelihood is above b's, per held-out range, and the
  // standard error of that lead from the per-fold differences.
  struct Lead {
    double per_range = 0.0;
    double standard_error = 0.0;
  };
  Lead lead_of(int a, int b) const {
    const Eigen::VectorXd difference =
        evidence_[static_cast<std::size_t>(a)].block_log_likelihood -
        evidence_[static_cast<std::size_t>(b)].block_log_likelihood;
    const double blocks = static_cast<double>(difference.size());
    const double variance =
        (difference.array() - difference.mean()).square().sum() / (blocks - 1.0);
    const double k = static_cast<double>(held_out_count_);
    return {difference.sum() / k, std::sqrt(blocks * variance) / k};
  }

  const CandidateEvidence& evidence(int index) const {
    return evidence_[static_cast<std::size_t>(index)];
  }

  double null_log_likelihood() {
    if (!null_log_likelihood_) null_log_likelihood_ = single_gaussian_log_likelihood(y_);
    return *null_log_likelihood_;
  }

  StructureChoice finish() {
    StructureChoice choice;
    choice.null_log_likelihood = null_log_likelihood();
    choice.candidates = evidence_;
    int best = -1;
    for (int i = 0; i < static_cast<int>(evidence_.size()); ++i) {
      const CandidateEvidence& e = evidence_[static_cast<std::size_t>(i)];
      if (!e.ok) continue;
      if (score(i) > score(best)) best = i;
      if (choice.best_by_glr < 0 ||
          e.glr > evidence_[static_cast<std::size_t>(choice.best_by_glr)].glr) {
        choice.best_by_glr = i;
      }
      if (choice.best_by_bic < 0 ||
          e.bic < evidence_[static_cast<std::size_t>(choice.best_by_bic)].bic) {
        choice.best_by_bic = i;
      }
    }
    if (best < 0) {
      std::ostringstream msg;
      msg << "no candidate structure of Eq. 8 could be trained";
      if (!evidence_.empty()) msg << "; the first failed with: " << evidence_.front().error;
      throw NumericalError(msg.str());
    }
    // The one-standard-error rule: the fewest parameters among the candidates whose held-out
    // log-likelihood is within one standard error of the best one's.
    choice.best_by_held_out = best;
    choice.chosen = best;
    for (int i = 0; i < static_cast<int>(evidence_.size()); ++i) {
      const CandidateEvidence& e = evidence_[static_cast<std::size_t>(i)];
      if (!e.ok) continue;
      const Lead lead = lead_of(best, i);
      const CandidateEvidence& chosen = evidence_[static_cast<std::size_t>(choice.chosen)];
      if (lead.per_range <= lead.standard_error &&
          (e.parameters < chosen.parameters ||
           (e.parameters == chosen.parameters && score(i) > score(choice.chosen)))) {
        choice.chosen = i;
      }
    }
    const Lead lead = lead_of(best, choice.chosen);
    choice.shortfall_per_range = lead.per_range;
    choice.shortfall_standard_error = lead.standard_error;
    const CandidateEvidence& chosen = evidence_[static_cast<std::size_t>(choice.chosen)];
    choice.held_out_ranges = held_out_count_;
    choice.basis = basis_of(chosen.family, chosen.order);
    choice.modes = chosen.modes;
    choice.fit = fits_[static_cast<std::size_t>(choice.chosen)];
    return choice;
  }

 private:
  // Σ of the held-out log-likelihood over each scored block's ranges, each fold's fit on the
  // other folds warm-started from the same fold's fit of the basis one order below (`fold_warm`,
  // its θ extended by a zero: the bases nest) or, without one, from the whole fit. The fold's own
  // fit is nearer its optimum than the whole fit, another data set's, along the slow direction
  // of EM, the exchange of weight between overlapping modes. Each fold's fit goes to `fold_fits`.
  Eigen::VectorXd score_held_out_blocks(const Eigen::MatrixXd& h, const EmTrainResult& whole,
                                        EmTrainOptions em,
                                        const std::vector<EmStartingPoint>& fold_warm,
                                        std::vector<EmStartingPoint>& fold_fits) const {
    em.start = EmStartingPoint{whole.theta, whole.mixture};
    fold_fits.assign(train_rows_.size(), EmStartingPoint{});
    // Each fold's held-out log-densities, fitted independently (possibly at once).
    const int folds = static_cast<int>(train_rows_.size());
    std::vector<Eigen::VectorXd> fold_log_density(train_rows_.size());
    std::vector<std::exception_ptr> fold_failure(train_rows_.size());
    const auto fit_fold = [&](int fold) {
      const auto f = static_cast<std::size_t>(fold);
      try {
        const std::vector<Eigen::Index>& train_rows = train_rows_[f];
        const std::vector<Eigen::Index>& held_rows = held_rows_[f];
        EmTrainOptions fold_em = em;
        if (f < fold_warm.size()) {
          fold_em.start = fold_warm[f];
          fold_em.log_likelihood_tolerance =
              std::max(em.log_likelihood_tolerance, kFoldLogLikelihoodTolerance);
        }
        const EmTrainResult fit = train_em(h(train_rows, Eigen::all), y_(train_rows), fold_em);
        fold_fits[f] = EmStartingPoint{fit.theta, fit.mixture};
        const Eigen::VectorXd residual = y_(held_rows) - h(held_rows, Eigen::all) * fit.theta;
        fold_log_density[f] =
            options_.resolution > 0.0
                ? rounded_mixture_log_probabilities(residual, fit.mixture, options_.resolution)
                : mixture_log_densities(residual, fit.mixture);
      } catch (...) {
        fold_failure[f] = std::current_exception();
      }
    };
    if (options_.parallel_for) {
      options_.parallel_for(folds, fit_fold);
    } else {
      for (int f = 0; f < folds; ++f) fit_fold(f);
    }
    // The first fold's failure, as a serial run would have met it.
    for (const std::exception_ptr& failure : fold_failure) {
      if (failure) std::rethrow_exception(failure);
    }
    // Summed in fold order whatever ran them.
    Eigen::VectorXd by_block = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(block_slot_.size()));
    for (std::size_t f = 0; f < train_rows_.size(); ++f) {
      const std::vector<Eigen::Index>& held_rows = held_rows_[f];
      const Eigen::VectorXd& log_density = fold_log_density[f];
      for (std::size_t i = 0; i < held_rows.size(); ++i) {
        by_block[block_slot_.at(held_rows[i] / block_)] +=
            log_density[static_cast<Eigen::Index>(i)];
      }
    }
    return by_block;
  }

  const Eigen::VectorXd& temperature_;
  const Eigen::VectorXd& y_;
  const StructureSearchOptions& options_;
  const SearchProgress& progress_;
  TemperatureScaling scaling_;
  Eigen::Index block_;  // options.block, or less on a short record
  double fourier_f0_per_c_ = 0.0;
  std::vector<std::vector<Eigen::Index>> train_rows_, held_rows_;  // per fold
  Eigen::Index held_out_count_ = 0;
  std::map<Eigen::Index, Eigen::Index> block_slot_;  // block → its entry in block sums
  std::map<std::tuple<std::string, int, int>, int> index_;
  std::vector<CandidateEvidence> evidence_;
  std::vector<EmTrainResult> fits_;
  std::vector<std::vector<EmStartingPoint>> fold_fits_;  // per candidate, per fold
  std::optional<double> null_log_likelihood_;
};

}  // namespace

Eigen::Index minimum_ranges_for_search(const StructureSearchOptions& options) {
  return options.folds * kMinimumRangesPerFold;
}

EmTrainOptions StructureSearchOptions::search_em_options() {
  EmTrainOptions em;
  em.log_likelihood_tolerance = kSearchLogLikelihoodTolerance;
  em.weight_tolerance = kSearchWeightTolerance;
  em.max_iterations = kSearchMaxIterations;
  em.record_trace = false;
  return em;
}

StructureChoice search_structure(const Eigen::Ref<const Eigen::VectorXd>& junction_temperature_c,
                                 const Eigen::Ref<const Eigen::VectorXd>& y_minus_d,
                                 const StructureSearchOptions& options,
                                 const SearchProgress& progress) {
  require_same_length(junction_temperature_c.size(), "junction temperature", y_minus_d.size(),
                      "y - d");
  require_finite(junction_temperature_c, "junction temperature");
  require_finite(y_minus_d, "y - d");
  if (options.folds < 2) throw InvalidInput("the structure search needs at least two folds");
  if (options.max_polynomial_order < 1 || options.max_modes < 1 || options.patience < 1 ||
      options.max_fourier_order < 0 || (options.modes && *options.modes < 1)) {
    throw InvalidInput(
        "the structure search needs max_polynomial_order, max_modes, patience and a fixed "
        "mode count >= 1, and max_fourier_order >= 0");
  }
  if (options.block < 1) throw InvalidInput("the structure search needs a block of >= 1 range");
  if (y_minus_d.size() < minimum_ranges_for_search(options)) {
    std::ostringstream msg;
    msg << "the structure search needs at least " << kMinimumRangesPerFold
        << " ranges per fold (" << minimum_ranges_for_search(options) << " for "
        << options.folds << " folds); found " << y_minus_d.size();
    throw InvalidInput(msg.str());
  }
  const Eigen::VectorXd temperature = junction_temperature_c;
  const Eigen::VectorXd y = y_minus_d;
  Search search(temperature, y, options, progress);

  if (options.basis) {
    // The user's basis: M alone.
    if (options.modes) {
      search.visit(kGiven, 0, *options.modes, std::nullopt);
    } else {
      search.scan_modes(kGiven, 0);
    }
    return search.finish();
  }
  // 1. The order at the paper's M = 2 (or the user's M).
  const int first_modes = options.modes.value_or(kPaperModes);
  const int best = search.scan_orders(kPolynomial, first_modes, options.max_polynomial_order);
  int modes = first_modes;
  if (!options.modes) {
    // 2. The number of modes at that order (order 1 when none could be trained with M = 2).
    const int order = best >= 0 ? search.evidence(best).order : 1;
    const int by_modes = search.scan_modes(kPolynomial, order);
    if (by_modes >= 0) modes = search.evidence(by_modes).modes;
    // 3. The orders again at that M.
    if (modes != first_modes) {
      search.scan_orders(kPolynomial, modes, options.max_polynomial_order);
    }
  }
  // 3. The Fourier family at that M.
  if (options.max_fourier_order > 0) {
    search.scan_orders(kFourier, modes, options.max_fourier_order);
  }
  return search.finish();
}

}  // namespace tofcomp::core
