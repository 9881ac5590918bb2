#include "cli/covariate_extension.hpp"

#include "cli/basis_spec.hpp"
#include "core/em_train.hpp"
#include "core/error.hpp"

namespace tofcomp::cli {
namespace {

constexpr double kRateHalfWindowS = 30.0;

// The covariate at each range: hours since the start, or the heating rate in °C/min.
Eigen::VectorXd covariate(core::EffectKind effect, const MeasuredData& data,
                          const Eigen::VectorXd& junction_c) {
  if (effect == core::EffectKind::TimeDrift) return data.range_time_s / 3600.0;
  return 60.0 * core::local_rate(data.range_time_s, junction_c, kRateHalfWindowS);
}

core::ErrorMoments window_errors(const MeasuredData& test, const Eigen::VectorXd& bias,
                                 const core::MixtureParameters& mixture, Eigen::Index window,
                                 Eigen::Index stride) {
  const core::WindowEstimates w =
      core::estimate_windows(test.range_mm, bias, mixture, window, stride);
  Eigen::VectorXd truth(static_cast<Eigen::Index>(w.start.size()));
  for (std::size_t i = 0; i < w.start.size(); ++i) {
    truth[static_cast<Eigen::Index>(i)] = test.true_range_mm.segment(w.start[i], window).mean();
  }
  return core::error_moments(w.em_distance, truth);
}

}  // namespace

bool has_covariate_extension(core::EffectKind effect) {
  return effect == core::EffectKind::TimeDrift || effect == core::EffectKind::HeatingHysteresis;
}

ExtensionReport evaluate_covariate_extension(core::EffectKind effect, const MeasuredData& train,
                                             const MeasuredData& test,
                                             const TrainSettings& settings, Eigen::Index window,
                                             Eigen::Index stride) {
  if (!has_covariate_extension(effect)) {
    throw core::InvalidInput(std::string("no covariate extension for ") +
                             core::effect_name(effect));
  }
  test.require_true_ranges();
  ExtensionReport report;
  report.effect = effect;
  report.covariate = effect == core::EffectKind::TimeDrift ? "time (h)" : "heating rate (°C/min)";
  report.window = window;

  // The paper's model.
  const Training base = train_calibration(train, settings);
  const Compensation test_base = compensate(test, base.calibration);
  report.before =
      window_errors(test, test_base.bias_mm, base.calibration.model.noise, window, stride);

  // The extended model: the same basis, one more column.
  const core::Basis& basis = base.calibration.model.basis;
  const auto extended_design = [&](const MeasuredData& data, const Eigen::VectorXd& junction) {
    Eigen::MatrixXd h(junction.size(), basis.columns() + 1);
    h.leftCols(basis.columns()) = basis.design_matrix(junction);
    h.col(basis.columns()) = covariate(effect, data, junction);
    return h;
  };
  const Eigen::MatrixXd h_train = extended_design(train, base.junction.junction_c);
  const core::EmTrainResult fit =
      core::train_em(h_train, train.range_mm - train.true_range_mm, settings.em);
  report.coefficient = fit.theta[fit.theta.size() - 1];
  const Eigen::VectorXd bias_after =
      extended_design(test, test_base.junction.junction_c) * fit.theta;
  report.after = window_errors(test, bias_after, fit.mixture, window, stride);
  report.kept = report.after.mean_absolute_error < report.before.mean_absolute_error;
  return report;
}

}  // namespace tofcomp::cli
