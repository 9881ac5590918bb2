#include "calibration/training.hpp"

#include "calibration/basis_spec.hpp"
#include "io/utc_time.hpp"
#include "io/version.hpp"

namespace tofcomp::calibration {

Training train_calibration(const MeasuredData& data, const TrainSettings& settings,
                           const MeasuredData* held_out) {
  data.require_true_ranges();
  Training t;
  t.thermal = fit_thermal(data, held_out, settings.thermal);
  const core::ThermalParameters& thermal = t.thermal.identified();
  t.junction =
      junction_at_ranges(data, thermal, settings.kalman_noise, settings.thermal.ambient_fallback_c);

  const core::Basis basis = parse_basis(settings.basis, t.junction.junction_c);
  const Eigen::MatrixXd h = basis.design_matrix(t.junction.junction_c);
  t.em = core::train_em(h, data.range_mm - data.true_range_mm, settings.em);

  core::Calibration& c = t.calibration;
  c.thermal = thermal;
  c.kalman_noise = settings.kalman_noise;
  c.ambient_c = settings.thermal.ambient_fallback_c;
  c.model.basis = basis;
  c.model.theta = t.em.theta;
  c.model.mixture = t.em.mixture;
  c.model.trained_junction_c =
      core::TemperatureRange{t.junction.junction_c.minCoeff(), t.junction.junction_c.maxCoeff()};
  c.provenance.data_set = data.source;
  c.provenance.created_utc = io::utc_now();
  c.provenance.software_version = std::string("tofcomp ") + io::kVersion;
  c.provenance.samples = static_cast<long>(data.range_mm.size());
  c.provenance.notes = "beam " + std::to_string(data.beam) + "; EM " +
                       std::to_string(t.em.iterations) + " iterations" +
                       (t.em.converged ? "" : " (iteration cap reached)");
  return t;
}

}  // namespace tofcomp::calibration
