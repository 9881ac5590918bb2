// Extending Eq. 8 by a covariate the diagnosis pointed to: y = d + H(t^j)θ + γ·c + w, with c
// the time (time drift) or the junction's heating rate (heating hysteresis). The covariate is
// one more column of the design, so EM training and testing keep their closed-form steps
// (§5, §6). Held-out data decide: the extension is kept only if it lowers the mean absolute
// error of the window estimate d̂ on the test part.
#pragma once

#include <optional>

#include "cli/pipeline.hpp"
#include "core/residual_diagnosis.hpp"

namespace tofcomp::cli {

struct ExtensionReport {
  core::EffectKind effect;
  std::string covariate;
  double coefficient = 0.0;  // γ, mm per unit of the covariate
  Eigen::Index window = 0;
  core::ErrorMoments before;  // d̂ of the paper's model on the held-out part
  core::ErrorMoments after;   // d̂ of the extended model
  bool kept = false;
};

// Whether the effect has a covariate extension here.
bool has_covariate_extension(core::EffectKind effect);

// Trains the paper's model and the extended one on `train`, compares d̂ on windows of
// `window` ranges (stride `stride`) of `test`. Throws core::InvalidInput for an effect without
// a covariate extension.
ExtensionReport evaluate_covariate_extension(core::EffectKind effect, const MeasuredData& train,
                                             const MeasuredData& test,
                                             const TrainSettings& settings, Eigen::Index window,
                                             Eigen::Index stride);

}  // namespace tofcomp::cli
