#include "calibration/model_search.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <limits>
#include <mutex>
#include <optional>
#include <random>
#include <utility>
#include <vector>

#include "calibration/covariates.hpp"
#include "calibration/model_spec.hpp"
#include "calibration/parallel_for.hpp"
#include "core/cramer_rao.hpp"
#include "core/error.hpp"
#include "core/estimators.hpp"
#include "core/sign_flip_max_t.hpp"
#include "core/statistical_tests.hpp"

namespace tofcomp::calibration {
namespace {

// Each fold gets at least this many blocks.
constexpr Eigen::Index kMinimumBlocksPerFold = 10;
// The gains are summed over runs of this many consecutive ranges for their t statistic: long
// enough to hold the serial dependence a slightly wrong model leaves within a few seconds of
// ranging, short enough for the many samples an effect concentrated in a few places needs.
constexpr Eigen::Index kStatisticRun = 100;
constexpr int kFolds = 2;
constexpr unsigned kFoldSeed = 20151211;
// EM of a candidate: stop when the log-likelihood moves less than this per range (a hundredth
// of a nat over 10^5 ranges), or after this many iterations.
constexpr double kFitTolerancePerRange = 1e-7;
constexpr int kFitIterations = 150;
// A time constant's profile: this many EM iterations at each τ, then this many golden-section
// steps between the best grid point's neighbours.
constexpr int kProfileIterations = 4;
constexpr int kGoldenSteps = 6;
// A direction of the bias that a fold holds less than this many ranges' worth of is not
// determined by it (SearchData). The folds' shares of a well-spread direction vary by tens of
// percent from one draw of the blocks to another (down to 4 % of 7,000 ranges, 260 ranges'
// worth, in the tests' clean records), and a direction so held is one no model the search
// compares can move; one a fold holds a few ranges' worth of is fitted to those ranges alone
// (or not at all: singular to working precision).
constexpr double kMinimumRangesPerDirection = 10.0;
// The screen (model_search.hpp): every candidate's short fit, this many EM iterations from the
// held model (from each of its starts; at the best τ of the grid), and the candidates fitted to
// convergence after it.
constexpr int kScreenIterations = 8;
// The outlier component's two starts (model_spec.hpp): the held modes, the trimmed residuals'.
constexpr int kOutlierStarts = 2;

// A model on one fold: its spec (a term's τ may differ between folds) and its fit on the fold's
// training ranges.
struct FoldModel {
  ModelSpec spec;
  core::ExtendedParameters fit;
};

// Blocks alternating between two folds. A fold's model scores the other fold's ranges whose
// junction temperature lies inside those it was trained on: beyond them compensation does not
// trust the basis (it continues the bias along its tangent, core/measurement_model.hpp), and a
// polynomial continued there would make every candidate that soaks up its error look good.
struct Folds {
  Eigen::Index block = 0;
  std::vector<int> block_of;                           // per range
  std::array<std::vector<Eigen::Index>, kFolds> rows;  // each fold's ranges
  std::array<std::vector<Eigen::Index>, kFolds> scored;  // what each fold's model scores
  std::vector<bool> is_scored;                         // per range
  std::vector<int> fold_of_block;
  int blocks = 0;
  const std::vector<Eigen::Index>& training(int f) const {
    return rows[static_cast<std::size_t>(f)];
  }
  const std::vector<Eigen::Index>& held_out(int f) const {
    return scored[static_cast<std::size_t>(f)];
  }
};

Folds make_folds(const Eigen::VectorXd& junction_c, const std::vector<Eigen::Index>& windows) {
  const Eigen::Index ranges = junction_c.size();
  const Eigen::Index longest =
      windows.empty() ? 0 : *std::max_element(windows.begin(), windows.end());
  const Eigen::Index most = ranges / (kFolds * kMinimumBlocksPerFold);
  if (most < 1) {
    throw core::InvalidInput(fmt::format(
        "the model search needs at least {} ranges ({} folds of {} blocks); the data have {}",
        kFolds * kMinimumBlocksPerFold, kFolds, kMinimumBlocksPerFold, ranges));
  }
  Folds f;
  f.block = std::max<Eigen::Index>(1, std::min(longest, most));
  f.block_of.resize(static_cast<std::size_t>(ranges));
  f.blocks = static_cast<int>((ranges + f.block - 1) / f.block);
  // Blocks go to the folds in a shuffled order (a fixed seed: the same data, the same folds),
  // half to each: alternating them would alias with a power schedule whose cycles hold an even
  // number of blocks and give one fold only the cycles' hot halves.
  std::vector<int> fold_of_block(static_cast<std::size_t>(f.blocks));
  for (int b = 0; b < f.blocks; ++b) fold_of_block[static_cast<std::size_t>(b)] = b % kFolds;
  std::mt19937 shuffle(kFoldSeed);
  std::shuffle(fold_of_block.begin(), fold_of_block.end(), shuffle);
  for (Eigen::Index k = 0; k < ranges; ++k) {
    const auto b = static_cast<int>(k / f.block);
    f.block_of[static_cast<std::size_t>(k)] = b;
    f.rows[static_cast<std::size_t>(fold_of_block[static_cast<std::size_t>(b)])].push_back(k);
  }
  f.fold_of_block = std::move(fold_of_block);
  f.is_scored.assign(static_cast<std::size_t>(ranges), false);
  for (int fold = 0; fold < kFolds; ++fold) {
    const auto& trained = f.rows[static_cast<std::size_t>(fold)];
    const Eigen::VectorXd t = junction_c(trained);
    const double lo = t.minCoeff(), hi = t.maxCoeff();
    for (const Eigen::Index k : f.rows[static_cast<std::size_t>(1 - fold)]) {
      if (junction_c[k] >= lo && junction_c[k] <= hi) {
        f.scored[static_cast<std::size_t>(fold)].push_back(k);
        f.is_scored[static_cast<std::size_t>(k)] = true;
      }
    }
  }
  return f;
}

// A fit to convergence (kFitIterations) runs SQUAREM; the short fits of a time constant's
// profile and of the screen (a few EM steps each, to rank them) run plain EM, so that "a few
// steps" means what it always did. (SQUAREM's eight M-steps in the screen moved a chain started
// at independence hardly further: 4.0e-3 against 3.4e-3 nats per range of the 2.5e-2 it reaches.)
core::ExtendedEmOptions em_options(double variance_floor, int iterations) {
  core::ExtendedEmOptions o;
  o.log_likelihood_tolerance = kFitTolerancePerRange;
  o.max_iterations = iterations;
  o.variance_floor = variance_floor;
  o.acceleration =
      iterations < kFitIterations ? core::EmAcceleration::None : core::EmAcceleration::Squarem;
  return o;
}

struct Fitted {
  FoldModel model;
  double log_likelihood = 0.0;
};

// A candidate's short fit, and what its fit to convergence goes on from: the best point of the
// τ grid (with its short fit's training log-likelihood) and the best start.
struct Screened {
  Fitted fitted;
  std::size_t grid_index = 0;
  double grid_value = -std::numeric_limits<double>::infinity();
  int start = 0;
};

// Fits spec + term on `rows` from the held model's fit there: τ profiled, several starts where
// the term has them. rows: the ranges to fit on (all when empty).
class TermFitter {
 public:
  TermFitter(const SearchData& data, double variance_floor)
      : data_(data), floor_(variance_floor) {}

  // The screen: τ at the best point of its grid, every start, kScreenIterations each; the best
  // by the training likelihood.
  Screened screen(const FoldModel& held, const core::Term& candidate,
                  const std::vector<Eigen::Index>& rows_or_all) const {
    const std::vector<Eigen::Index> rows = all_rows_if_empty(rows_or_all, data_.size());
    Screened out;
    // The term's constants (a linear form's centre, scale and range, the knots) from the
    // ranges it is fitted on: a fold's fit must not know the covariate values it is scored on.
    double tau = candidate.time_constant_s;
    if (candidate.needs_time_constant()) {
      const auto& grid = core::kTimeConstantGridS;
      for (std::size_t i = 0; i < grid.size(); ++i) {
        const double v = short_fit(held, on_rows(candidate, grid[i], rows), rows);
        if (v > out.grid_value) out.grid_value = v, out.grid_index = i;
      }
      tau = grid[out.grid_index];
    }
    const core::Term term = on_rows(candidate, tau, rows);
    std::optional<Fitted> best;
    for (int s = 0; s < starts_of(held, term); ++s) {
      Fitted f = run(held, term, rows, s, kScreenIterations);
      if (!best || f.log_likelihood > best->log_likelihood) best = std::move(f), out.start = s;
    }
    out.fitted = std::move(*best);
    return out;
  }

  // To convergence, from the screen: τ refined by a golden-section search in log τ between the
  // grid's best point's neighbours (a better τ starts again from the held model; otherwise the
  // screened fit goes on).
  Fitted fit(const FoldModel& held, const core::Term& candidate, const Screened& screened,
             const std::vector<Eigen::Index>& rows_or_all) const {
    const std::vector<Eigen::Index> rows = all_rows_if_empty(rows_or_all, data_.size());
    if (candidate.needs_time_constant()) {
      const std::optional<core::Term> refined =
          refine_time_constant(held, candidate, screened, rows);
      if (refined) return run(held, *refined, rows, screened.start, kFitIterations);
    }
    const core::ExtendedDesign design = design_of(
        screened.fitted.model.spec, data_, screened.fitted.model.fit.model.modes.modes(), rows);
    const core::ExtendedEmResult em = core::train_extended_em(
        design, data_.y()(rows), screened.fitted.model.fit, em_options(floor_, kFitIterations));
    return {FoldModel{screened.fitted.model.spec, em.fit}, em.log_likelihood};
  }

  // The screen and the fit to convergence at once (the kept terms' fit on all the data).
  Fitted fit(const FoldModel& held, const core::Term& candidate,
             const std::vector<Eigen::Index>& rows_or_all) const {
    return fit(held, candidate, screen(held, candidate, rows_or_all), rows_or_all);
  }

 private:
  // One more mode is split from each held mode; the outlier component has kOutlierStarts.
  static int starts_of(const FoldModel& held, const core::Term& term) {
    if (term.parameter == core::Parameter::ExtraMode) return held.fit.model.modes.modes();
    if (term.parameter == core::Parameter::Outliers) return kOutlierStarts;
    return 1;
  }

  Fitted run(const FoldModel& held, const core::Term& term, const std::vector<Eigen::Index>& rows,
             int start, int iterations) const {
    Extended ext = with_term(held.spec, held.fit, term, data_, rows, start);
    const core::ExtendedDesign design =
        design_of(ext.spec, data_, ext.start.model.modes.modes(), rows);
    const core::ExtendedEmResult em = core::train_extended_em(
        design, data_.y()(rows), ext.start, em_options(floor_, iterations));
    return {FoldModel{std::move(ext.spec), em.fit}, em.log_likelihood};
  }

  // The term at time constant τ, its constants from `rows`.
  core::Term on_rows(const core::Term& t, double tau, const std::vector<Eigen::Index>& rows) const {
    return data_.covariates().make_term(t.parameter, t.covariate, t.form, t.mode, tau, rows,
                                        static_cast<int>(t.knots.size()));
  }

  double short_fit(const FoldModel& held, const core::Term& t,
                   const std::vector<Eigen::Index>& rows) const {
    try {
      return run(held, t, rows, 0, kProfileIterations).log_likelihood;
    } catch (const core::Error&) {
      return -std::numeric_limits<double>::infinity();
    }
  }

  // The golden-section search in log τ between the grid's best point's neighbours; the term at
  // the τ it found when that beats the grid's point, none otherwise.
  std::optional<core::Term> refine_time_constant(const FoldModel& held, const core::Term& t,
                                                 const Screened& screened,
                                                 const std::vector<Eigen::Index>& rows) const {
    const auto& grid = core::kTimeConstantGridS;
    const std::size_t best = screened.grid_index;
    double lo = std::log(grid[best == 0 ? 0 : best - 1]);
    double hi = std::log(grid[std::min(best + 1, grid.size() - 1)]);
    const double ratio = (std::sqrt(5.0) - 1.0) / 2.0;
    double a = hi - ratio * (hi - lo), b = lo + ratio * (hi - lo);
    const auto value = [&](double log_tau) {
      return short_fit(held, on_rows(t, std::exp(log_tau), rows), rows);
    };
    double fa = value(a), fb = value(b);
    for (int step = 0; step < kGoldenSteps; ++step) {
      if (fa >= fb) {
        hi = b, b = a, fb = fa;
        a = hi - ratio * (hi - lo);
        fa = value(a);
      } else {
        lo = a, a = b, fa = fb;
        b = lo + ratio * (hi - lo);
        fb = value(b);
      }
    }
    if (std::max(fa, fb) <= screened.grid_value) return std::nullopt;
    return on_rows(t, fa >= fb ? std::exp(a) : std::exp(b), rows);
  }

  const SearchData& data_;
  double floor_;
};

// The term a spec holds for the candidate it was given (its τ as profiled, its mode).
core::Term last_added(const ModelSpec& spec, const core::Term& candidate) {
  switch (candidate.parameter) {
    case core::Parameter::Bias:
      return spec.bias_terms.back();
    case core::Parameter::ModeOffset:
      return spec.offset_terms.back();
    case core::Parameter::Weights:
      return *spec.weight_term;
    case core::Parameter::Spread:
      return *spec.variance_term;
    default:
      return candidate;
  }
}

// log p of each held-out range under a fold's model (rounded values), written at their places.
void score_held_out(const SearchData& data, const FoldModel& model,
                    const std::vector<Eigen::Index>& held_out, double resolution,
                    Eigen::VectorXd& scores) {
  const core::ExtendedDesign design =
      design_of(model.spec, data, model.fit.model.modes.modes(), held_out);
  const Eigen::VectorXd residual = data.y()(held_out) - design.shared * model.fit.theta;
  const Eigen::VectorXd s =
      core::extended_log_scores(residual, design.state,
                                core::mode_shifts(design, model.fit.mode_coefficients),
                                model.fit.model, resolution);
  scores(held_out) = s;
}

// Held-out gains of two candidates closer than this share of the named one's are one model's
// (they differ by rounding).
constexpr double kRoundingGainShare = 1e-9;

// P(T ≥ t) for Student's T with runs − 1 degrees of freedom.
double one_sided_p(double t, double runs) { return core::student_upper_tail(t, runs - 1.0); }

struct BlockTest {
  Eigen::VectorXd run_gains;  // the gains summed over each run of consecutive scored ranges
  double gain = 0.0;
  double t = 0.0;
  double p = 1.0;
};

// The gains summed over runs of consecutive scored ranges, and Student's t of their mean.
BlockTest block_test(const Eigen::VectorXd& gain, const Folds& folds) {
  const Eigen::Index run = std::min(kStatisticRun, folds.block);
  std::vector<double> runs;
  Eigen::Index in_run = 0;
  for (Eigen::Index k = 0; k < gain.size(); ++k) {
    if (!folds.is_scored[static_cast<std::size_t>(k)]) continue;
    if (in_run == 0) runs.push_back(0.0);
    runs.back() += gain[k];
    in_run = (in_run + 1) % run;
  }
  BlockTest out;
  out.run_gains =
      Eigen::Map<const Eigen::VectorXd>(runs.data(), static_cast<Eigen::Index>(runs.size()));
  if (out.run_gains.size() < 2) return out;
  out.gain = out.run_gains.sum();
  const core::BlockGainTest test = core::block_gain_t_test(out.run_gains);
  out.t = test.t;
  out.p = test.p;
  return out;
}

// d̂'s absolute errors on the windows inside the held-out blocks of one fold's model.
void held_out_window_errors(const SearchData& data, const FoldModel& model, const Folds& folds,
                            int fold, Eigen::Index window, Eigen::Index stride,
                            std::vector<double>& errors) {
  const core::ExtendedDesign design =
      design_of(model.spec, data, model.fit.model.modes.modes(), {});
  const Eigen::VectorXd bias = design.shared * model.fit.theta;
  const Eigen::MatrixXd shift = core::mode_shifts(design, model.fit.mode_coefficients);
  for (int b = 0; b < folds.blocks; ++b) {
    if (folds.fold_of_block[static_cast<std::size_t>(b)] == fold) continue;  // trained on it
    const Eigen::Index first = b * folds.block;
    const Eigen::Index length = std::min(folds.block, data.size() - first);
    if (length < window) continue;
    // Only a block the fold's model scores whole: its temperatures inside those it trained on.
    bool whole = true;
    for (Eigen::Index k = first; k < first + length; ++k) {
      whole = whole && folds.is_scored[static_cast<std::size_t>(k)];
    }
    if (!whole) continue;
    const core::WindowEstimates e = core::estimate_windows(
        data.y().segment(first, length), bias.segment(first, length),
        design.state.segment(first, length),
        shift.size() > 0 ? Eigen::MatrixXd(shift.middleRows(first, length)) : Eigen::MatrixXd(0, 0),
        model.fit.model, window, stride);
    for (Eigen::Index i = 0; i < e.em_distance.size(); ++i) {
      errors.push_back(std::abs(e.em_distance[i]));  // y − d: the truth is zero
    }
  }
}

// d̂'s absolute errors on the held-out windows of one model (its fit on each fold), per window
// length of options.windows that fits in a block, the folds joined in fold order. Each model's
// are computed once: a step compares the held model's with its named candidate's, and the end
// the training's with the final model's.
using WindowErrors = std::vector<std::vector<double>>;

// The windows a held-out block holds (`fits` true) or does not.
std::vector<Eigen::Index> windows_by_fit(const Folds& folds, const ModelSearchOptions& options,
                                         bool fits) {
  std::vector<Eigen::Index> windows;
  for (const Eigen::Index w : options.windows) {
    if ((w <= folds.block) == fits) windows.push_back(w);
  }
  return windows;
}

std::vector<Eigen::Index> compared_windows(const Folds& folds, const ModelSearchOptions& options) {
  return windows_by_fit(folds, options, true);
}

WindowErrors window_errors_of(const SearchData& data, const std::array<FoldModel, kFolds>& model,
                              const Folds& folds, const ModelSearchOptions& options, int threads) {
  const std::vector<Eigen::Index> windows = compared_windows(folds, options);
  // Each (window, fold) apart, computed at once, then joined in that order.
  const int tasks = static_cast<int>(windows.size()) * kFolds;
  std::vector<std::vector<double>> errors(static_cast<std::size_t>(tasks));
  parallel_for(tasks, threads, [&](int task) {
    const int f = task % kFolds;
    held_out_window_errors(data, model[static_cast<std::size_t>(f)], folds, f,
                           windows[static_cast<std::size_t>(task / kFolds)], options.stride,
                           errors[static_cast<std::size_t>(task)]);
  });
  WindowErrors out(windows.size());
  for (std::size_t wi = 0; wi < windows.size(); ++wi) {
    for (int f = 0; f < kFolds; ++f) {
      const std::vector<double>& e = errors[wi * kFolds + static_cast<std::size_t>(f)];
      out[wi].insert(out[wi].end(), e.begin(), e.end());
    }
  }
  return out;
}

// The bound is that of the better model's modes: a term that explains part of the noise (a drift
// the paper's modes had widened to hold) tightens the modes, and with them the bound.
std::vector<HeldOutError> compare_held_out(const WindowErrors& before, const WindowErrors& after,
                                           const core::MixtureParameters& after_modes,
                                           const Folds& folds, const ModelSearchOptions& options) {
  // The fitted modes hold the rounding's variance: the bound takes the modes before it
  // (core::modes_before_rounding, as evaluate_windows does).
  const double range_information = core::range_fisher_information(
      core::modes_before_rounding(after_modes, options.resolution), options.resolution);
  const std::vector<Eigen::Index> windows = compared_windows(folds, options);
  const auto mean = [](const std::vector<double>& v) {
    double s = 0.0;
    for (const double x : v) s += x;
    return s / static_cast<double>(v.size());
  };
  std::vector<HeldOutError> out;
  for (std::size_t wi = 0; wi < windows.size(); ++wi) {
    if (before[wi].empty()) continue;
    out.push_back({windows[wi], static_cast<Eigen::Index>(before[wi].size()), mean(before[wi]),
                   mean(after[wi]), core::cramer_rao_mae_mm(range_information, windows[wi])});
  }
  return out;
}

// The outlier component of a calibration's extension, as the grammar's term.
std::optional<core::Term> carried_outliers(const core::Calibration& base) {
  if (!base.extension || !(base.extension->extended_mixture.outlier_weight > 0.0)) {
    return std::nullopt;
  }
  core::Term t;
  t.parameter = core::Parameter::Outliers;
  t.covariate = core::Covariate::None;
  t.form = core::Form::None;
  return t;
}

// The candidates a step fits to convergence (model_search.hpp): of the first `count` effects
// (labels) in `order`, among the candidates screened without error, the first of each form. The
// screen ranks the variants of one form fairly (the smooth form's knot counts alike), but not one
// form against another: a decay's or a lag's τ is only on its grid until the fit to convergence
// refines it, so a form without a τ gets ahead in the screen by what the grid's spacing costs.
std::vector<std::size_t> best_forms_of_best_effects(const std::vector<std::size_t>& order,
                                                    const std::vector<CandidateResult>& candidates,
                                                    int count) {
  std::vector<core::EffectLabel> effects;
  for (const std::size_t c : order) {
    const CandidateResult& r = candidates[c];
    if (!r.ok() || std::find(effects.begin(), effects.end(), r.term.label()) != effects.end()) {
      continue;
    }
    if (static_cast<int>(effects.size()) >= count) break;
    effects.push_back(r.term.label());
  }
  std::vector<std::size_t> out;
  std::vector<std::pair<core::EffectLabel, core::Form>> held;
  for (const std::size_t c : order) {
    const CandidateResult& r = candidates[c];
    if (!r.ok() || std::find(effects.begin(), effects.end(), r.term.label()) == effects.end()) {
      continue;
    }
    const std::pair<core::EffectLabel, core::Form> effect_form{r.term.label(), r.term.form};
    if (std::find(held.begin(), held.end(), effect_form) != held.end()) continue;
    held.push_back(effect_form);
    out.push_back(c);
  }
  return out;
}

// The family-wise level (model_search.hpp): the null law of the largest t over every candidate
// of a step, those fitted to convergence by their final gains, the others by their screen's.
// `order` ranks the candidates, its first one judged; `run_gains` are indexed by candidate.
core::SignFlipMaxT step_max_t(const std::vector<std::size_t>& order,
                              const std::vector<Eigen::VectorXd>& run_gains) {
  const Eigen::Index runs = run_gains[order.front()].size();
  std::vector<std::size_t> judged;
  for (const std::size_t c : order) {
    if (run_gains[c].size() == runs) judged.push_back(c);
  }
  Eigen::MatrixXd gains(runs, static_cast<Eigen::Index>(judged.size()));
  for (std::size_t j = 0; j < judged.size(); ++j) {
    gains.col(static_cast<Eigen::Index>(j)) = run_gains[judged[j]];
  }
  return core::SignFlipMaxT(gains);
}

}  // namespace

Eigen::Index ModelSearchResult::scored_ranges() const {
  return static_cast<Eigen::Index>(std::count(scored.begin(), scored.end(), true));
}

std::vector<const CandidateResult*> SearchStep::not_told_apart() const {
  std::vector<const CandidateResult*> out;
  for (const CandidateResult& c : candidates) {
    if (c.not_told_apart_from_named()) out.push_back(&c);
  }
  return out;
}

std::vector<core::Term> grammar_candidates(const core::CovariateTable& covariates, int modes) {
  using core::Covariate;
  using core::Form;
  using core::Parameter;
  std::vector<core::Term> out;
  const double tau = core::kTimeConstantGridS[core::kTimeConstantGridS.size() / 2];
  const auto add_made = [&](const std::function<core::Term()>& make) {
    try {
      out.push_back(make());
    } catch (const core::InvalidInput&) {
      // A covariate these data hold constant (one power-on, no ambient change), or with too few
      // distinct values for so many knots: no candidate.
    }
  };
  const auto add = [&](Parameter p, Covariate c, Form f, int mode) {
    if (c != Covariate::None && !covariates.available(c)) return;
    if (f != Form::Smooth) {
      return add_made([&] { return covariates.make_term(p, c, f, mode, tau); });
    }
    // The smooth form once per knot count: the held-out scores choose among them as among forms.
    for (const int knots : core::kSmoothKnotCounts) {
      add_made([&] { return covariates.make_term(p, c, f, mode, tau, {}, knots); });
    }
  };
  for (const Covariate c : {Covariate::Time, Covariate::HeatingRate, Covariate::Ambient}) {
    add(Parameter::Bias, c, Form::Linear, -1);
    add(Parameter::Bias, c, Form::Smooth, -1);
  }
  add(Parameter::Bias, Covariate::TimeSincePowerOn, Form::Decay, -1);
  add(Parameter::Bias, Covariate::TimeSincePowerOn, Form::Smooth, -1);
  add(Parameter::Bias, Covariate::JunctionLag, Form::Linear, -1);
  for (int i = 0; i < modes; ++i) {
    for (const Covariate c : {Covariate::JunctionTemperature, Covariate::HeatingRate,
                              Covariate::Time, Covariate::Ambient}) {
      add(Parameter::ModeOffset, c, Form::Linear, i);
    }
    add(Parameter::ModeOffset, Covariate::TimeSincePowerOn, Form::Decay, i);
  }
  // The spreads and the weights: a log-variance or log-odds slope on each covariate (a decay
  // after power-on), and free bins of the junction temperature for a dependence that is not
  // monotone.
  for (const Parameter p : {Parameter::Spread, Parameter::Weights}) {
    for (const Covariate c : {Covariate::JunctionTemperature, Covariate::HeatingRate,
                              Covariate::Time, Covariate::Ambient}) {
      add(p, c, Form::Linear, -1);
    }
    add(p, Covariate::TimeSincePowerOn, Form::Decay, -1);
    add(p, Covariate::JunctionTemperature, Form::Bins, -1);
  }
  for (const Parameter p : {Parameter::Markov, Parameter::ExtraMode, Parameter::Outliers}) {
    add(p, Covariate::None, Form::None, -1);
  }
  return out;
}

std::size_t named_position(const std::vector<CandidateResult>& ranked, double critical_t) {
  const auto first_passing = std::find_if(
      ranked.begin(), ranked.end(), [&](const CandidateResult& r) { return r.passes(critical_t); });
  return first_passing == ranked.end()
             ? 0
             : static_cast<std::size_t>(first_passing - ranked.begin());
}

namespace {

// The outlier component training gave the gross errors (calibration/gross_errors.hpp) is the
// model the search starts from; any other extension is left aside and searched for again.
core::Calibration without_extension(core::Calibration calibration) {
  calibration.extension.reset();
  return calibration;
}

}  // namespace

// What a search holds between its steps.
struct ModelSearchRun::State {
  State(const MeasuredData& data, const core::Calibration& base, const SmoothedJunction& junction,
        const ModelSearchOptions& search_options, ModelSearchProgress search_progress)
      : options(search_options),
        progress(std::move(search_progress)),
        calibration(without_extension(base)),
        carried(carried_outliers(base)),
        folds(make_folds(junction.junction_c, options.windows)),
        search_data(data.range_mm - data.true_range_mm,
                    calibration.model.basis.design_matrix(junction.junction_c),
                    covariate_table(data, junction), calibration.model.theta,
                    folds.training(0), kMinimumRangesPerDirection),
        floor(options.resolution * options.resolution / 12.0),
        fitter(search_data, floor),
        threads(thread_count(options.threads)) {}

  void report(double share, const std::string& stage) {
    if (!progress) return;
    const std::lock_guard<std::mutex> lock(progress_mutex);
    progress(share, stage);
  }

  // The training's model fitted to convergence on `rows` (all when empty).
  FoldModel fit_base(const std::vector<Eigen::Index>& rows) const {
    const core::ExtendedDesign design =
        design_of(base_spec, search_data, calibration.model.mixture.modes(), rows);
    const Eigen::VectorXd y =
        rows.empty() ? search_data.y() : Eigen::VectorXd(search_data.y()(rows));
    return FoldModel{base_spec, core::train_extended_em(design, y, base_fit,
                                                        em_options(floor, kFitIterations))
                                    .fit};
  }

  void run_step();
  void drop_redundant_terms();
  // Each fold's model without the step at `left_out`: the base model with the other held steps'
  // terms, fitted in their order.
  std::array<FoldModel, kFolds> held_without(std::size_t left_out) const;
  bool was_dropped(const core::EffectLabel& label) const;
  void hold(const std::array<FoldModel, kFolds>& models, WindowErrors errors);

  const ModelSearchOptions options;
  const ModelSearchProgress progress;
  std::mutex progress_mutex;
  const core::Calibration calibration;  // the training's, its extension left aside
  const std::optional<core::Term> carried;
  const Folds folds;
  const SearchData search_data;
  const double floor;
  const TermFitter fitter;
  const int threads;
  core::ExtendedParameters base_fit;
  ModelSpec base_spec;
  ModelSearchResult result;  // its steps, the kept carried term; the rest at the end
  std::array<FoldModel, kFolds> held;
  std::array<FoldModel, kFolds> base_held;  // the training's model on each fold
  Eigen::VectorXd held_scores;
  WindowErrors training_errors;
  WindowErrors held_errors;
  bool finished = false;
  // result()'s fits on all the data: the base model, then one per held step with its term
  // added (the steps' positions in all_data_steps).
  mutable std::vector<FoldModel> all_data_fits;
  mutable std::vector<std::size_t> all_data_steps;
};

ModelSearchRun::ModelSearchRun(const MeasuredData& data, const core::Calibration& base,
                               const SmoothedJunction& junction,
                               const ModelSearchOptions& options,
                               const ModelSearchProgress& progress) {
  data.require_true_ranges();
  state_ = std::make_unique<State>(data, base, junction, options, progress);
  State& s = *state_;
  const std::optional<core::Term>& carried = s.carried;
  s.result.block = s.folds.block;
  s.result.blocks = s.folds.blocks;
  s.result.windows_not_compared = windows_by_fit(s.folds, options, false);
  s.result.basis_directions_held = s.search_data.directions_undetermined_by_a_half();

  // The training's model on each fold, from its fit on all the data.
  const core::Calibration& calibration = s.calibration;
  s.base_fit = core::ExtendedParameters{
      Eigen::VectorXd(),
      std::vector<Eigen::VectorXd>(static_cast<std::size_t>(calibration.model.mixture.modes())),
      core::without_extensions(calibration.model.mixture)};
  s.search_data.to_orthogonal(calibration.model.theta, s.base_fit.theta,
                              s.base_fit.model.modes.mean);
  if (carried) {
    s.base_spec.outliers = true;
    s.base_spec.effects.push_back(carried->label());
    s.base_fit.model.outlier_weight = base.extension->extended_mixture.outlier_weight;
    s.base_fit.model.outlier_density = base.extension->extended_mixture.outlier_density;
    s.result.kept.push_back(*carried);
    s.result.carried_from_training = 1;
  }
  s.held_scores = Eigen::VectorXd::Zero(s.search_data.size());
  // The folds at once: each writes its own model and its own held-out rows' scores.
  parallel_for(kFolds, s.threads, [&](int f) {
    s.held[static_cast<std::size_t>(f)] = s.fit_base(s.folds.training(f));
    score_held_out(s.search_data, s.held[static_cast<std::size_t>(f)], s.folds.held_out(f),
                   options.resolution, s.held_scores);
  });
  s.base_held = s.held;
  s.result.base_held_out_log_likelihood = s.held_scores.sum();
  s.training_errors = window_errors_of(s.search_data, s.held, s.folds, options, s.threads);
  s.held_errors = s.training_errors;
  s.finished = options.max_steps < 1;
}

ModelSearchRun::~ModelSearchRun() = default;
ModelSearchRun::ModelSearchRun(ModelSearchRun&&) noexcept = default;
ModelSearchRun& ModelSearchRun::operator=(ModelSearchRun&&) noexcept = default;

bool ModelSearchRun::finished() const { return state_->finished; }

const std::vector<SearchStep>& ModelSearchRun::steps() const { return state_->result.steps; }

bool ModelSearchRun::next_step() {
  if (state_->finished) return false;
  state_->run_step();
  return true;
}

void ModelSearchRun::State::run_step() {
  const int step = static_cast<int>(result.steps.size());
  const int modes = held[0].fit.model.modes.modes();
  std::vector<core::Term> candidates;
  for (const core::Term& t : grammar_candidates(search_data.covariates(), modes)) {
    if (held[0].spec.accepts(t) && !was_dropped(t.label())) candidates.push_back(t);
  }
  if (candidates.empty()) {
    finished = true;
    return;
  }
  SearchStep s;
  s.candidates.resize(candidates.size());
  std::vector<std::array<FoldModel, kFolds>> fits(candidates.size());
  std::vector<std::array<Screened, kFolds>> screens(candidates.size());
  std::vector<Eigen::VectorXd> run_gains(candidates.size());  // per candidate, as last judged
  // A candidate fitted on each fold (by fit_on(fold)) and scored on the other: its result.
  const auto judge = [&](std::size_t c, const std::function<Fitted(int)>& fit_on) {
    CandidateResult& r = s.candidates[c];
    try {
      Eigen::VectorXd scores = Eigen::VectorXd::Zero(search_data.size());
      for (int f = 0; f < kFolds; ++f) {
        Fitted fitted = fit_on(f);
        if (f == 0) r.term = last_added(fitted.model.spec, candidates[c]);
        score_held_out(search_data, fitted.model, folds.held_out(f), options.resolution, scores);
        fits[c][static_cast<std::size_t>(f)] = std::move(fitted.model);
      }
      BlockTest test = block_test(scores - held_scores, folds);
      run_gains[c] = std::move(test.run_gains);
      r.held_out_gain = test.gain;
      r.gain_per_range = test.gain / static_cast<double>(search_data.size());
      r.t_statistic = test.t;
      r.p_value = test.p;
    } catch (const core::Error& e) {
      r.error = e.what();
    }
  };
  // refined_effects 0: every candidate is fitted to convergence (no screen decides anything).
  const bool refine_all = options.refined_effects == 0;
  std::atomic<int> done{0};
  const double step_share = 1.0 / options.max_steps;
  // The step's fits: every screen, then the fits to convergence, refined_effects of them as an
  // estimate until the screen has chosen them (then as many as it chose).
  double work = static_cast<double>(
      candidates.size() + (refine_all ? candidates.size()
                                      : std::min<std::size_t>(
                                            static_cast<std::size_t>(options.refined_effects),
                                            candidates.size())));
  const auto progress_of = [&](const CandidateResult& r, const char* stage) {
    report(step_share * (step + static_cast<double>(++done) / work),
           fmt::format("step {}: {} {}", step + 1, stage, r.term.describe()));
  };
  // The screen: every candidate's short fit.
  parallel_for(static_cast<int>(candidates.size()), threads, [&](int i) {
    const auto c = static_cast<std::size_t>(i);
    s.candidates[c].term = candidates[c];
    s.candidates[c].screened_only = true;
    judge(c, [&](int f) {
      const auto fold = static_cast<std::size_t>(f);
      screens[c][fold] = fitter.screen(held[fold], candidates[c], folds.training(f));
      return screens[c][fold].fitted;
    });
    progress_of(s.candidates[c], "screened");
  });
  // The `refined` best by the screen's held-out gain, fitted to convergence from their screens.
  const auto by_gain = [&](std::vector<std::size_t>& order) {
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      const CandidateResult &x = s.candidates[a], &y = s.candidates[b];
      if (x.ok() != y.ok()) return x.ok();
      if (x.screened_only != y.screened_only) return !x.screened_only;
      return x.held_out_gain > y.held_out_gain;
    });
  };
  std::vector<std::size_t> order(candidates.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  by_gain(order);
  // Every candidate screened without error, or the best effects' forms.
  std::vector<std::size_t> to_refine;
  if (refine_all) {
    for (const std::size_t c : order) {
      if (s.candidates[c].ok()) to_refine.push_back(c);
    }
  } else {
    to_refine = best_forms_of_best_effects(order, s.candidates, options.refined_effects);
  }
  // Between the parallel loops, so no progress report reads it as it changes.
  work = static_cast<double>(candidates.size() + to_refine.size());
  parallel_for(static_cast<int>(to_refine.size()), threads, [&](int j) {
    const std::size_t c = to_refine[static_cast<std::size_t>(j)];
    s.candidates[c].screened_only = false;
    judge(c, [&](int f) {
      const auto fold = static_cast<std::size_t>(f);
      return fitter.fit(held[fold], candidates[c], screens[c][fold], folds.training(f));
    });
    progress_of(s.candidates[c], "fitted");
  });
  // Rank: those fitted to convergence by held-out gain, then the screened ones, failed last.
  by_gain(order);
  std::optional<core::SignFlipMaxT> max_t;
  if (s.candidates[order.front()].ok()) {
    max_t.emplace(step_max_t(order, run_gains));
    s.critical_t = max_t->critical_t(options.alpha);
    s.critical_p =
        one_sided_p(s.critical_t, static_cast<double>(run_gains[order.front()].size()));
  }
  std::vector<CandidateResult> ranked;
  for (const std::size_t i : order) ranked.push_back(s.candidates[i]);
  // The named candidate first, the others in rank order.
  const auto named_at =
      max_t ? static_cast<std::ptrdiff_t>(named_position(ranked, s.critical_t)) : 0;
  std::rotate(order.begin(), order.begin() + named_at, order.begin() + named_at + 1);
  std::rotate(ranked.begin(), ranked.begin() + named_at, ranked.begin() + named_at + 1);
  s.candidates = std::move(ranked);
  const auto fitted_count = std::count_if(s.candidates.begin(), s.candidates.end(),
                                          [](const CandidateResult& r) { return r.ok(); });
  result.candidates_per_step =
      std::max(result.candidates_per_step, static_cast<int>(fitted_count));
  const CandidateResult* named = s.named();
  if (named) {
    // Each other candidate fitted to convergence against the named one, run by run.
    for (std::size_t j = 1; j < order.size(); ++j) {
      CandidateResult& r = s.candidates[j];
      const Eigen::VectorXd& mine = run_gains[order[j]];
      const Eigen::VectorXd& named_runs = run_gains[order.front()];
      if (!r.ok() || r.screened_only || mine.size() != named_runs.size()) continue;
      Eigen::VectorXd difference = named_runs - mine;
      // One model reached by two terms (the same design) differs by rounding alone, which a t
      // statistic, blind to scale, would read as a difference of consistent sign.
      if (difference.cwiseAbs().sum() <= kRoundingGainShare * named_runs.cwiseAbs().sum()) {
        difference.setZero();
      }
      const core::BlockGainTest test = core::block_gain_t_test(difference);
      r.compared_with_named = true;
      r.t_below_named = test.t;
      r.p_below_named = test.p;
    }
    s.family_wise_p = max_t->adjusted_p(named->t_statistic);
    const std::array<FoldModel, kFolds>& best = fits[order.front()];
    const WindowErrors best_errors = window_errors_of(search_data, best, folds, options, threads);
    s.errors =
        compare_held_out(held_errors, best_errors, best[0].fit.model.modes, folds, options);
    s.kept = named->passes(s.critical_t);
    if (s.kept) hold(best, best_errors);
  }
  const bool kept = s.kept;
  result.steps.push_back(std::move(s));
  if (kept) drop_redundant_terms();
  finished = !kept || static_cast<int>(result.steps.size()) >= options.max_steps;
}

void ModelSearchRun::State::hold(const std::array<FoldModel, kFolds>& models,
                                 WindowErrors errors) {
  held = models;
  held_errors = std::move(errors);
  for (int f = 0; f < kFolds; ++f) {
    score_held_out(search_data, held[static_cast<std::size_t>(f)], folds.held_out(f),
                   options.resolution, held_scores);
  }
}

bool ModelSearchRun::State::was_dropped(const core::EffectLabel& label) const {
  return std::any_of(result.steps.begin(), result.steps.end(), [&](const SearchStep& s) {
    return s.dropped && s.named()->term.label() == label;
  });
}

std::array<FoldModel, kFolds> ModelSearchRun::State::held_without(std::size_t left_out) const {
  std::array<FoldModel, kFolds> out = base_held;
  for (int f = 0; f < kFolds; ++f) {
    FoldModel& model = out[static_cast<std::size_t>(f)];
    for (std::size_t i = 0; i < result.steps.size(); ++i) {
      const SearchStep& step = result.steps[i];
      if (i == left_out || !step.held()) continue;
      model = fitter.fit(model, step.named()->term, folds.training(f)).model;
    }
  }
  return out;
}

// Backward elimination (model_search.hpp), after the last step kept a term.
void ModelSearchRun::State::drop_redundant_terms() {
  const int after_step = static_cast<int>(result.steps.size());
  for (;;) {
    std::vector<std::size_t> earlier;  // the held steps before the last
    for (std::size_t i = 0; i + 1 < result.steps.size(); ++i) {
      if (result.steps[i].held()) earlier.push_back(i);
    }
    if (earlier.empty()) return;
    // Without each earlier term at once; one that cannot be refitted without stays.
    std::vector<std::optional<std::array<FoldModel, kFolds>>> without(earlier.size());
    parallel_for(static_cast<int>(earlier.size()), threads, [&](int j) {
      try {
        without[static_cast<std::size_t>(j)] = held_without(earlier[static_cast<std::size_t>(j)]);
      } catch (const core::Error&) {
      }
    });
    std::optional<std::size_t> weakest;  // of `earlier`
    for (std::size_t j = 0; j < earlier.size(); ++j) {
      if (!without[j]) continue;
      Eigen::VectorXd scores = Eigen::VectorXd::Zero(search_data.size());
      for (int f = 0; f < kFolds; ++f) {
        score_held_out(search_data, (*without[j])[static_cast<std::size_t>(f)],
                       folds.held_out(f), options.resolution, scores);
      }
      const BlockTest test = block_test(held_scores - scores, folds);
      SearchStep& step = result.steps[earlier[j]];
      step.judged_again_after_step = after_step;
      step.gain_beside_later = test.gain;
      step.t_beside_later = test.t;
      step.p_beside_later = test.p;
      const bool still_passes = test.gain > 0.0 && test.p <= options.alpha;
      if (!still_passes && (!weakest || test.p > result.steps[earlier[*weakest]].p_beside_later)) {
        weakest = j;
      }
    }
    if (!weakest) return;
    SearchStep& dropped = result.steps[earlier[*weakest]];
    dropped.dropped = true;
    const std::array<FoldModel, kFolds>& models = *without[*weakest];
    hold(models, window_errors_of(search_data, models, folds, options, threads));
    report(static_cast<double>(after_step) / options.max_steps,
           fmt::format("step {}: dropped {}", after_step, dropped.named()->term.describe()));
  }
}

const core::Calibration& calibration_to_deploy(const core::Calibration& trained,
                                               const ModelSearchResult* search) {
  return search && !search->kept.empty() ? search->calibration : trained;
}

ModelSearchResult ModelSearchRun::result() const {
  const State& s = *state_;
  ModelSearchResult result = s.result;
  // The kept terms fitted on all the data, in the order the search added them; the fits an
  // earlier call made (a search paused for the structure re-check, then run on) are taken again.
  // A carried component was fitted with the modes held (its weight alone); here every parameter
  // with it, as each fold's held model was, and as a kept term is.
  // A dropped term leaves the fits from its own on to be made again.
  std::vector<FoldModel>& fits = s.all_data_fits;
  std::vector<std::size_t>& fitted_steps = s.all_data_steps;
  if (fits.empty()) fits.push_back(s.carried ? s.fit_base({}) : FoldModel{s.base_spec, s.base_fit});
  std::size_t held_count = 0;
  for (std::size_t i = 0; i < result.steps.size(); ++i) {
    const SearchStep& step = result.steps[i];
    if (!step.held()) continue;
    if (held_count < fitted_steps.size() && fitted_steps[held_count] != i) {
      fitted_steps.resize(held_count);
      fits.resize(held_count + 1);
    }
    ++held_count;
    if (fits.size() <= held_count) {
      fits.push_back(s.fitter.fit(fits.back(), step.named()->term, {}).model);
      fitted_steps.push_back(i);
    }
    result.kept.push_back(last_added(fits[held_count].spec, step.named()->term));
  }
  const FoldModel& all = fits[held_count];
  result.calibration = calibration_of(all.spec, all.fit, s.calibration, s.search_data);
  if (result.kept.size() > static_cast<std::size_t>(result.carried_from_training)) {
    result.calibration.provenance.notes += "; extended by the model search";
  }
  result.errors = compare_held_out(s.training_errors, s.held_errors, s.held[0].fit.model.modes,
                                   s.folds, s.options);
  result.final_held_out_scores = s.held_scores;
  result.scored = s.folds.is_scored;
  return result;
}

ModelSearchResult search_model(const MeasuredData& data, const core::Calibration& base,
                               const SmoothedJunction& junction,
                               const ModelSearchOptions& options,
                               const ModelSearchProgress& progress) {
  ModelSearchRun run(data, base, junction, options, progress);
  while (run.next_step()) {
  }
  ModelSearchResult result = run.result();
  if (progress) progress(1.0, "done");
  return result;
}

}  // namespace tofcomp::calibration
