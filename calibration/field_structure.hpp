// The field fit's basis (calibration/field_training.hpp): Legendre polynomials of rising order, and
// the bench calibration's own basis when it is another (a Fourier term whose frequency was chosen
// on the bench's few kelvin), chosen as training chooses a structure (held-out likelihood of rounded ranges, core/structure_search.hpp) but on
// ranges whose distances are nuisance parameters: the ranges are dealt into two folds by
// alternating blocks of time, so that every long still episode has ranges in both; each order is
// fitted on one fold and scored on the other with the distances its fit gave the episodes there
// (an episode with no range in the fitting fold is not scored), and both ways summed. Orders rise
// from 1 until `patience` in a row fail to beat the best. A bench calibration's band is a few
// kelvin, its basis chosen there; a day in a hall spans tens of kelvin, where the bias's shape
// needs its own.
#pragma once

#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

#include "core/basis.hpp"
#include "core/field_em.hpp"

namespace tofcomp::calibration {

// The fold blocks: 10 minutes, longer than a lasing mode's dwell and the junction's time
// constants (tens of seconds), shorter than the still episodes (min_episode_s and up).
inline constexpr double kFieldFoldBlockS = 600.0;
inline constexpr int kFieldMaxOrder = 16;
inline constexpr int kFieldOrderPatience = 2;

struct FieldBasisChoice {
  core::Basis basis;  // scaled to the junction temperatures given
  std::vector<std::pair<std::string, double>> held_out;  // (basis, log-likelihood per range)
};

// The ranges of the fit: junction temperature, y, episode (core/field_em.hpp), time. `em` gives
// the modes, floor and start of each fit; `bench` is the bench calibration's basis (a candidate
// unless it is one Legendre polynomial, whose orders are tried anyway).
FieldBasisChoice choose_field_basis(const Eigen::Ref<const Eigen::VectorXd>& junction_c,
                                    const Eigen::Ref<const Eigen::VectorXd>& y,
                                    const std::vector<int>& episode, int episodes,
                                    const Eigen::Ref<const Eigen::VectorXd>& time_s,
                                    const core::FieldEmOptions& em, const core::Basis& bench);

}  // namespace tofcomp::calibration
