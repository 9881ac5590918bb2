// A sentence of the grammar (core/effect_grammar.hpp) being fitted by the model search
// (calibration/model_search.hpp): the terms the search holds so far, the design they give on
// any set of ranges, and the neutral start of one more term, so that its EM begins exactly where
// the model without it ended (each new coefficient at zero, each new bin at the pooled value, a
// chain that starts as independent draws would be, ...).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "core/calibration.hpp"
#include "core/covariate_table.hpp"
#include "core/extended_em.hpp"
#include "core/model_extension.hpp"

namespace tofcomp::calibration {

// What one search needs of the data, computed once: y − d, the basis design and the covariates.
// The basis design is H(t̂^j) centred and orthogonalized, Q = (H − 1h̄) P R⁻¹ (a column-pivoted
// thin QR, scaled so that QᵀQ = K I, directions below a relative 1e-10 of the largest dropped):
// the same fitted bias up to the constant the mode offsets carry, but conditioned on any half of
// the ranges, where a high-order basis the structure search chose on all of them (a Fourier
// series over a few kelvin is nearly constant) can be singular to working precision.
//
// Each half must determine the bias too. The search fits every model on one half of the ranges
// (`half_rows`) and on the other. Since QᵀQ = K I, the two halves' Gram matrices G and K I − G
// share their eigenvectors: a direction v of Q carries the share s = vᵀGv / K of its weight on
// the first half and 1 − s on the second, s·K and (1 − s)·K ranges' worth (a range carries one
// on average). A direction either half holds less than `minimum_half_ranges` ranges' worth of
// (a basis order the structure search fitted to a few ranges at one end of the temperatures,
// all in one block, say) is not determined there. Its coordinate is held at the training's fit
// (`held_theta`, which saw all the ranges): that part of the bias is subtracted from y − d, and
// Q, rotated onto the eigenvectors, keeps the directions both halves determine. (Dropping the
// direction instead would drop with it the little of the smooth bias its eigenvector mixes in.)
// When every direction is determined Q is left as the QR gave it and y − d as given.
class SearchData {
 public:
  SearchData(Eigen::VectorXd y_minus_d, const Eigen::MatrixXd& basis_design,
             core::CovariateTable covariates, const Eigen::VectorXd& held_theta,
             const std::vector<Eigen::Index>& half_rows, double minimum_half_ranges);
  Eigen::Index size() const { return y_.size(); }
  const Eigen::VectorXd& y() const { return y_; }  // y − d, less the bias held (above)
  const Eigen::MatrixXd& basis_design() const { return basis_design_; }  // Q
  // Directions of the centred basis held at the training's fit because one half of the ranges
  // does not determine them (the QR's rank-deficient ones aside).
  Eigen::Index directions_undetermined_by_a_half() const { return undetermined_by_a_half_; }
  const core::CovariateTable& covariates() const { return covariates_; }
  // The paper's θ and mode offsets in Q's coordinates, and back (the offsets shift by h̄θ; back,
  // the held directions' coordinates are added).
  void to_orthogonal(const Eigen::VectorXd& basis_theta, Eigen::VectorXd& theta,
                     Eigen::VectorXd& mean) const;
  void to_basis(const Eigen::VectorXd& orthogonal_theta, Eigen::VectorXd& theta,
                Eigen::VectorXd& mean) const;
  // The term's columns and bins on every range (not cached: the search's threads share this).
  Eigen::MatrixXd columns(const core::Term& term) const { return covariates_.columns(term); }
  Eigen::VectorXi bins(const core::Term& term) const { return covariates_.bins(term); }

 private:
  // A θ of H's columns as coordinates in Q, as Q stands (in the constructor, before its rotation).
  Eigen::VectorXd coordinates_of(const Eigen::VectorXd& basis_theta) const;

  Eigen::VectorXd y_;
  Eigen::MatrixXd basis_design_;
  Eigen::RowVectorXd column_mean_;  // h̄
  Eigen::MatrixXd basis_centred_;   // H − 1h̄, for the projection of a θ onto Q
  Eigen::MatrixXd r_;               // the retained columns' R (r × r)
  Eigen::MatrixXd rotation_;        // Q's columns in the QR's (r × columns of Q)
  Eigen::VectorXd held_coordinates_;  // the held directions' part of the bias, in the QR's
  Eigen::Index undetermined_by_a_half_ = 0;
  std::vector<Eigen::Index> retained_;  // those columns of H
  core::CovariateTable covariates_;
};

struct ModelSpec {
  std::vector<core::Term> bias_terms;    // their columns follow H's, in this order
  std::vector<core::Term> offset_terms;  // each mode's columns in this order
  std::optional<core::Term> weight_term;
  std::optional<core::Term> variance_term;
  bool chain = false;
  bool outliers = false;
  int extra_modes = 0;
  std::vector<core::EffectLabel> effects;  // as added

  // Whether a term can join: not the label of one already held, one binning per noise parameter,
  // no chain beside binned weights or outliers.
  bool accepts(const core::Term& term) const;
};

// `rows`, or every range 0 … n − 1 when it is empty (the searches' "all the data").
std::vector<Eigen::Index> all_rows_if_empty(const std::vector<Eigen::Index>& rows, Eigen::Index n);

// The design of a spec on the given ranges (all when empty): [H, the bias terms' columns], each
// mode's offset columns, each range's noise state.
core::ExtendedDesign design_of(const ModelSpec& spec, const SearchData& data, int modes,
                               const std::vector<Eigen::Index>& rows);

// The spec with one more term, and the start of its fit from the parameters of the spec without
// it (fitted on `rows`): new coefficients zero, bins at the pooled values, the chain at
// A = ½I + ½1πᵀ, the outlier component at a small weight over the residuals' span, one more
// mode split from mode `split_mode` (the search tries each).
struct Extended {
  ModelSpec spec;
  core::ExtendedParameters start;
};
Extended with_term(const ModelSpec& spec, const core::ExtendedParameters& fitted,
                   const core::Term& term, const SearchData& data,
                   const std::vector<Eigen::Index>& rows, int split_mode = 0);

// The fitted spec as a calibration: the base calibration's thermal part and basis, θ's basis part
// (back from Q to H) and the modes from the fit, the rest as a core::ModelExtension (none when the
// spec is empty).
core::Calibration calibration_of(const ModelSpec& spec, const core::ExtendedParameters& fitted,
                                 const core::Calibration& base, const SearchData& data);

// The number of free parameters a spec's fit has beyond the paper's (for reports).
int added_parameters(const ModelSpec& spec, int modes);

}  // namespace tofcomp::calibration
