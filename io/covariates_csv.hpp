// The covariates of the grammar (core/effect_grammar.hpp) at each range of a record, as CSV: what
// the model search saw, for a user who wants to plot a residual against it (`tofcomp diagnose
// --covariates-output`). One row per range: its time, the base model's centred residual
// y − d − H(t̂^j)θ̂ − Σ π_i μ_i, then each covariate the data carry in its unit (the ambient only
// when logged), then the junction's lag L_τ(t̂^j) − t̂^j at each time constant of the search's
// grid.
#pragma once

#include <Eigen/Core>
#include <ostream>

#include "core/covariate_table.hpp"

namespace tofcomp::io {

// Throws core::InvalidInput when the times, the residuals and the table differ in length.
void write_covariates_csv(std::ostream& out, const Eigen::Ref<const Eigen::VectorXd>& time_s,
                          const Eigen::Ref<const Eigen::VectorXd>& residual_mm,
                          const core::CovariateTable& covariates);

}  // namespace tofcomp::io
