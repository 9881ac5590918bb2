#include "cli/search_residuals.hpp"

#include <limits>

#include "calibration/covariates.hpp"
#include "core/extended_mixture.hpp"

namespace tofcomp::cli {

SearchResiduals search_residuals(const calibration::MeasuredData& measured,
                                 const core::Calibration& calibration) {
  measured.require_true_ranges();
  calibration::Compensation compensation = calibration::compensate(measured, calibration);
  core::CovariateTable covariates = calibration::covariate_table(measured, compensation.junction);
  SearchResiduals out{std::move(compensation),
                      std::move(covariates),
                      core::compensation_mixture(calibration),
                      {},
                      {},
                      {},
                      {}};
  const calibration::Compensation& c = out.compensation;
  out.residual = measured.range_mm - measured.true_range_mm - c.bias_mm;
  core::ExtendedResponsibilities r;
  core::extended_e_step(out.residual, c.noise_state, c.mode_shift, out.mixture, r);
  out.responsibility = r.mode;
  const Eigen::Index n = out.residual.size();
  out.mode.resize(n);
  out.e.resize(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    Eigen::Index best = 0;
    const double p = r.mode.row(k).maxCoeff(&best);
    if (r.outlier.size() == n && r.outlier[k] > p) {
      out.mode[k] = kOutlierMode;
      out.e[k] = std::numeric_limits<double>::quiet_NaN();
      continue;
    }
    const auto i = static_cast<int>(best);
    out.mode[k] = i;
    const double shift = c.mode_shift.size() > 0 ? c.mode_shift(k, i) : 0.0;
    out.e[k] = out.residual[k] - out.mixture.modes.mean[i] - shift;
  }
  return out;
}

}  // namespace tofcomp::cli
