// Closing the loop: a search over the grammar of core/effect_grammar.hpp for what Eq. 8 lacks,
// judged on held-out ranges, one term at a time (forward selection).
//
// Held out how. The ranges are cut into blocks of L consecutive ranges (L the longest window
// of the d̂ comparison, fewer on a short record so that each fold has at least ten blocks), and
// the blocks alternate between two folds. Every model — the one held so far and each candidate
// with one more term — is fitted on each fold by the closed-form EM of core/extended_em.hpp
// (warm-started where the model without the term ended) and scores the other fold's ranges:
// log p(y_k − d | the model fitted without them), each range by the probability of its rounded
// value (core::extended_log_scores; under a chain the one-step predictive probability). So every
// range is scored once, by a fit that never saw it.
//
// Which term, and whether to keep it. A candidate's gain is the sum over all ranges of its score
// less the held model's. Given the junction temperatures, blocks are independent under the held
// model, so the blocks' gains are a sample: with n blocks, t = mean / (sd / √n) is Student's t
// with n − 1 degrees of freedom when the candidate adds nothing, and a candidate fitted on other
// data that adds nothing cannot gain on average (its extra parameters only cost). The level is
// the point that the largest t of the step's candidates passes by chance with probability α:
// the max-T method, its null law drawn by flipping the signs of the same runs for every
// candidate (core/sign_flip_max_t.hpp). Named: the candidate with the largest gain among those
// whose t passes the level; kept: it, when there is one; when none passes, the largest gain is
// named and nothing kept. Because the level holds for all the step's candidates at once, the
// chance that data with nothing missing keep anything at all is at most α whichever passing
// candidate is named, and candidates that gain on the same ranges (one covariate in several
// forms, one term on each mode) count about once, where α / m (Bonferroni) counted each. Naming
// the largest gain outright let a gain made in a few runs (a power-on's transient: t 2.0, under
// the level) hide one that most runs show (t 4.1, a little less gain), and keep neither. Then
// the search goes on from the model with the kept term (forward selection), until nothing more
// passes or max_steps steps have run.
//
// Backward elimination. A term kept first can be a neighbour of the effect a later step finds
// (a warm-up after power-on where the thermal network lacks a state: the state explains the
// power-ons and the rest): once the later term is held, the first may add nothing. So after a
// step keeps a term, each term an earlier step kept is judged again: the held model is refitted
// on each fold without it (the other held terms in their order), and the held-out gain of
// keeping it is tested on the same runs. That is one test of a named term, not a choice among
// the step's candidates, so its level is α itself (Student's one-sided p), not the max-T level
// that admitted the term: a term admitted near that level moves across it between two fits of
// the same terms (measured on a blind set: an ambient bias kept at t 3.19 against 2.93 and
// judged again at t 2.62, still 32.8 nats of gain, whose drop raised d̂'s error by a quarter).
// When the gain is not positive or its p is above α, the term with the largest p is dropped and
// the others are judged again. A dropped effect is not a candidate again (no cycle). Dropping
// only ever removes terms, so the chance of keeping anything on data with nothing missing is
// unchanged.
//
// A screen, then fits to convergence. Every candidate first gets a short fit on each fold (a
// few EM iterations from the held model) and is scored on the other fold as above; only the few
// effects best by that held-out gain (ModelSearchOptions::refined_effects) are then fitted to
// convergence, going on from their short fits, and scored again: of each, the best candidate of
// each form (the smooth form's knot counts would otherwise fill the few places with variants of
// one explanation and leave out the next one, which a fit to convergence may rank first; one
// form per effect would let the screen choose between forms, which it does not rank fairly: a
// decay's τ is refined off its grid only in the fit to convergence, and on a warm-up the screen
// put a 17-knot smooth form ahead of the decay that beats it after convergence, by 1,281 against
// 1,218 nats). The named term is the best of those. Why a short fit ranks: started at the held
// model's fixed point, EM's first M-step solves the new mean term exactly given the
// responsibilities (and a spread's or weights' slope by a Newton step), so a term the data
// support shows most of its gain there; what the rest of the iterations add is the slow exchange
// between the modes, which every candidate shares. The max-T law takes every candidate of the
// step, the screened ones by their short fits' gains (standing in for the fits to convergence
// they did not get: those rank them, and a gain's dependence on the others comes from the ranges
// it is made on); only a candidate fitted to convergence can be named and kept.
//
// A term's shape (a linear form's centre, scale and covariate range, the knots, the bins' edges)
// is taken from the fold's own training ranges, never from the ranges it is scored on, and its
// time constant (a decay's τ, the junction lag's τ) is profiled on them too: a few EM
// iterations at each τ of a grid (the screen), then, for a candidate fitted to convergence, a
// golden-section search between the best point's neighbours. One more
// mode is tried split from each mode, the outlier component from the held modes and from the
// trimmed residuals' modes; the best start by the training likelihood is the screen's, and goes
// on to convergence.
//
// The held-out error of d̂ (§6, §8.4) before and after each named term, per window length:
// windows inside each held-out block, d̂ under the fold's models. The kept terms are finally
// fitted on all the data into the calibration (τ profiled again on all of it).
#pragma once

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "calibration/measured_data.hpp"
#include "calibration/junction_estimate.hpp"
#include "core/calibration.hpp"
#include "core/effect_grammar.hpp"
#include "core/extended_em.hpp"

namespace tofcomp::calibration {

struct ModelSearchOptions {
  double alpha = 0.05;  // the family-wise false-alarm level of the whole search
  int max_steps = 3;    // steps at most (each names a term; a kept one is added)
  std::vector<Eigen::Index> windows{200, 400, 800};
  Eigen::Index stride = 10;  // ranges between windows of the d̂ comparison
  double resolution = kRangeResolutionMm;
  int threads = 0;  // candidates fitted at once; 0: one per core
  // Effects fitted to convergence after the screen (each form of each), the best by their
  // held-out gain; 0: every candidate (no screen decides anything).
  int refined_effects = kRefinedEffects;
  static constexpr int kRefinedEffects = 4;
};

// The level at which a candidate is told apart from the named one: the named candidate's
// held-out gain over it, run by run, one-sided.
inline constexpr double kToldApartLevel = 0.05;

struct CandidateResult {
  core::Term term;    // as fitted on the first fold (its τ there)
  std::string error;  // why it could not be fitted; empty when it was
  double held_out_gain = 0.0;  // nats over every range, each scored by the fold that left it out
  double gain_per_range = 0.0;
  double t_statistic = 0.0;  // of the blocks' gains
  double p_value = 1.0;      // one-sided, Student's t with blocks − 1 degrees of freedom
  bool screened_only = false;  // the figures are the screen's short fit's (not fitted to the end)
  // Beside the named candidate, when this one was fitted to convergence too: Student's t of the
  // named one's held-out gain less this one's over the same runs, and its one-sided p. Above
  // kToldApartLevel, these data do not tell this candidate from the named one: another
  // explanation of the same misfit, as the paper's model sees it.
  bool compared_with_named = false;
  double t_below_named = 0.0;
  double p_below_named = 1.0;
  bool ok() const { return error.empty(); }
  // Past a step's family-wise level: fitted to convergence, gaining, its t above critical_t. The
  // step names the first such candidate and keeps it (named_position).
  bool passes(double critical_t) const {
    return ok() && !screened_only && held_out_gain > 0.0 && t_statistic > critical_t;
  }
  bool not_told_apart_from_named() const {
    return compared_with_named && p_below_named > kToldApartLevel;
  }
};

// d̂'s mean absolute error on held-out windows of one length before and after a term.
struct HeldOutError {
  Eigen::Index window = 0;
  Eigen::Index windows = 0;
  double before_mae_mm = 0.0;
  double after_mae_mm = 0.0;
  double cramer_rao_mae_mm = 0.0;  // under the modes of the model after the term
};

struct SearchStep {
  // The named candidate first (named_position), then the others ranked: those fitted to
  // convergence by held-out gain, then the screened ones, failed last.
  std::vector<CandidateResult> candidates;
  // The family-wise threshold: a candidate passes when its t exceeds critical_t (the max-T
  // law's 1 − α point), and the named one is kept when it passes; critical_p is that t's
  // one-sided Student p, for reading beside each candidate's p_value; family_wise_p the named
  // candidate's adjusted p under the law.
  double critical_t = 0.0;
  double critical_p = 0.0;
  double family_wise_p = 1.0;
  bool kept = false;
  // A kept term judged again after a later step kept one (backward elimination, above): the
  // last such step (1-based; 0 when none), and the comparison there, the model held after it
  // against that model refitted without this term: the held-out gain of keeping the term (nats),
  // its t and one-sided p. When the gain was not positive or the p above α, it was dropped there.
  int judged_again_after_step = 0;
  double gain_beside_later = 0.0;
  double t_beside_later = 0.0;
  double p_beside_later = 1.0;
  bool dropped = false;
  std::vector<HeldOutError> errors;  // of the named (first) candidate
  bool held() const { return kept && !dropped; }
  const CandidateResult* named() const {
    return !candidates.empty() && candidates.front().ok() ? &candidates.front() : nullptr;
  }
  // The candidates these data do not tell from the named one, in rank order.
  std::vector<const CandidateResult*> not_told_apart() const;
};

struct ModelSearchResult {
  std::vector<SearchStep> steps;
  std::vector<core::Term> kept;       // held at the end, in the order added, fitted on all the data
  // The first kept terms came with the training's calibration rather than from a step: its
  // outlier component for gross errors (calibration/gross_errors.hpp), 0 or 1.
  int carried_from_training = 0;
  core::Calibration calibration;      // the training's model with the kept terms, on all the data
  std::vector<HeldOutError> errors;   // the training's model against the final one
  // The held-out log-likelihood of the scored ranges (each scored by the fold that left it
  // out), under the final model: per range (0 where not scored) and summed; the training's
  // model's sum. A range is scored when its junction temperature lies inside the other fold's
  // (no extrapolation), so the count depends on the junction estimate: compare two searches
  // per scored range, not by the sums.
  std::vector<bool> scored;  // per range
  Eigen::VectorXd final_held_out_scores;
  double base_held_out_log_likelihood = 0.0;
  double final_held_out_log_likelihood() const { return final_held_out_scores.sum(); }
  Eigen::Index scored_ranges() const;
  Eigen::Index block = 0;             // ranges per block
  Eigen::Index blocks = 0;
  // The d̂ windows of options.windows longer than a block, which no held-out block holds (the
  // blocks shrink on a short record): the errors above leave them out.
  std::vector<Eigen::Index> windows_not_compared;
  int candidates_per_step = 0;
  // Directions of the training's bias the search held at the training's fit: one half of the
  // ranges does not determine them (SearchData); the calibration it writes keeps them so.
  Eigen::Index basis_directions_held = 0;
};

// The calibration to deploy after a search from `trained`: the search's where it kept a term, the
// trained one bit for bit where it kept nothing (`search` null: no search ran).
const core::Calibration& calibration_to_deploy(const core::Calibration& trained,
                                               const ModelSearchResult* search);

using ModelSearchProgress = std::function<void(double share, const std::string& stage)>;

// The search on data with a known distance, from the paper's model trained on them (its thermal
// model, basis, θ and modes; an extension it may carry is left aside) and their smoothed junction
// temperature under it; an outlier component it carries (training's, for gross errors) stays in
// every model the search compares and heads `kept`. Throws core::InvalidInput
// when the data are too short for two folds of ten blocks, and core::Error when the held model
// cannot be fitted on a fold.
ModelSearchResult search_model(const MeasuredData& data, const core::Calibration& base,
                               const SmoothedJunction& junction,
                               const ModelSearchOptions& options = {},
                               const ModelSearchProgress& progress = {});

// The same search one step at a time, for a caller that decides between the steps (the
// structure re-check, calibration/structure_recheck.hpp, looks again at the structure as soon as
// a term on the bias is kept). search_model is: construct, next_step() until it returns false,
// result(). `data` must outlive the run.
class ModelSearchRun {
 public:
  // Fits the training's model on each fold (throws as search_model does).
  ModelSearchRun(const MeasuredData& data, const core::Calibration& base,
                 const SmoothedJunction& junction, const ModelSearchOptions& options = {},
                 const ModelSearchProgress& progress = {});
  ~ModelSearchRun();
  ModelSearchRun(ModelSearchRun&&) noexcept;
  ModelSearchRun& operator=(ModelSearchRun&&) noexcept;

  // Runs the next step; false, running none, once the search has ended: a step kept nothing,
  // options.max_steps steps ran, or no candidate is left.
  bool next_step();
  bool finished() const;
  const std::vector<SearchStep>& steps() const;
  // The search as it stands: the terms kept so far fitted on all the data, the errors of the
  // model they make.
  ModelSearchResult result() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// Which of a step's candidates, ranked by gain as SearchStep::candidates are, the step names (its
// position): the first fitted to convergence with a positive gain whose t exceeds critical_t;
// without one, the first.
std::size_t named_position(const std::vector<CandidateResult>& ranked, double critical_t);

// The candidates of the grammar for a model with `modes` modes, on the covariates available:
// every bias form, each mode's offset, a slope of the spreads and of the weights on every
// covariate (and their bins of the junction temperature), the chain, one more mode and the
// outlier component (time constants still to be profiled).
std::vector<core::Term> grammar_candidates(const core::CovariateTable& covariates, int modes);

}  // namespace tofcomp::calibration
