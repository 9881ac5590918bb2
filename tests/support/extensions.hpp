// Extensions of Eq. 8 written by hand for tests (core/model_extension.hpp): one bias term on a
// covariate in its raw units, or a structure on the paper's modes.
#pragma once

#include "core/model_extension.hpp"

namespace tofcomp::testing {

// A bias term γ f(c): linear in the covariate's own units (centre 0, scale 1), or a decay
// exp(−c/τ).
inline core::Term raw_bias_term(core::Covariate covariate, core::Form form,
                                double time_constant_s = 0.0) {
  core::Term t;
  t.parameter = core::Parameter::Bias;
  t.covariate = covariate;
  t.form = form;
  t.time_constant_s = time_constant_s;
  return t;
}

// The paper's modes with one bias term of coefficient gamma_mm.
inline core::ModelExtension bias_extension(const core::MixtureParameters& modes,
                                           core::Covariate covariate, core::Form form,
                                           double gamma_mm, double time_constant_s = 0.0) {
  core::ModelExtension x;
  const core::Term t = raw_bias_term(covariate, form, time_constant_s);
  x.effects.push_back(t.label());
  x.mean_terms.push_back({t, Eigen::VectorXd::Constant(1, gamma_mm)});
  x.extended_mixture = core::without_extensions(modes);
  return x;
}

// The paper's modes named as one structural effect (its parts set by the caller).
inline core::ModelExtension structure_extension(const core::MixtureParameters& modes,
                                                core::Parameter structure) {
  core::ModelExtension x;
  x.effects.push_back({structure, core::Covariate::None});
  x.extended_mixture = core::without_extensions(modes);
  return x;
}

}  // namespace tofcomp::testing
