// The tables behind the figure of one term of the model search (cli/search_figure_data.hpp), as
// CSV text, computed on the residuals of the whole record under the final calibration
// (cli/search_residuals.hpp). Each takes the term and, when the search kept it, what the
// calibration holds of it; without that (a candidate not kept) the fitted columns are empty and
// the figure shows the data and the model held, no fitted effect. Every number a figure draws is
// here: the renderer (cli/report/) bins and plots, it evaluates no model.
#pragma once

#include <Eigen/Core>
#include <string>

#include "cli/search_residuals.hpp"
#include "core/effect_grammar.hpp"
#include "core/extended_mixture.hpp"
#include "core/model_extension.hpp"

namespace tofcomp::cli {

// A bias or mode-offset term. Ranges: covariate, partial_residual_mm (e with the term's own
// contribution added back, so that the term's curve is what it should follow), mode (0-based,
// −1 an outlier), in_term (1 where the term acts: every range but outliers for a bias term, the
// ranges of its mode for a mode-offset term; elsewhere the partial residual is empty).
std::string mean_term_ranges_csv(const SearchResiduals& r, const core::Term& term,
                                 const core::MeanTermFit* fit);
// The fitted contribution over the covariate's span: covariate, fitted_mm. A kept term only.
std::string mean_term_curve_csv(const SearchResiduals& r, const core::MeanTermFit& fit);

// A spread or weights term, per bin of its covariate and mode: bin (1-based), low, high (the
// bin's edges, the outer ones at the covariate's extremes), covariate_mean (of the bin's ranges),
// mode (1-based), ranges (of the mode in the bin, Σ_k r_ki over the bin's ranges: the posteriors,
// as overlapping modes share ranges), observed (the bin's spread of the mode,
// √(Σ r_ki (y_k − d − bias − μ_i − shift_ki)² / Σ r_ki), or its share Σ r_ki / Σ_j Σ r_kj: what
// one M-step on the bin's ranges gives, so that a kept term's fitted values sit on them; empty
// under 10 ranges), fitted (σ = √ of the calibration's variance, or its weight; empty when not
// kept), held (the model's single value without the term; empty when kept).
std::string bins_term_csv(const SearchResiduals& r, const core::Term& term,
                          const core::NoiseBins* fit);

// The modes as a Markov chain: per mode (1-based) and run length 1..60: observed (runs of the
// most probable mode of that length), chain (expected under the fitted chain, R_i (1 − a_ii)
// a_ii^(L−1), R_i the mode's observed runs; empty when not kept), independent (the same under
// independent draws, a_ii replaced by π_i).
std::string runs_csv(const SearchResiduals& r, const Eigen::MatrixXd* transition);

// One more mode, outliers: the calibration's mixture density of y − d − bias (1/mm) over a grid
// of the residuals' span, averaged over the ranges' noise states and mode shifts: residual_mm,
// mode1..modeM, outliers (with an outlier component), total.
std::string density_csv(const SearchResiduals& r);

// The residuals themselves: time_s, residual_mm, mode, e_mm.
std::string residuals_csv(const calibration::MeasuredData& measured, const SearchResiduals& r);

}  // namespace tofcomp::cli
