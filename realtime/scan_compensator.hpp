// The compensation of one scan, beam by beam (Eq. 8 and §6 in real time): each range y of a
// beam becomes y − H(t̂^j)θ̂ (the bias at the scan's junction temperature, one value for the
// whole scan), fed to the beam's sliding-window EM estimator (core/sliding_window_estimator.hpp)
// for d̂ and its standard deviation, and published compensated by its most probable mode:
// y − H(t̂^j)θ̂ − μ_î. Ranges with no echo are published as such and do not enter the window.
// Without a calibration or a junction temperature the raw ranges are published with the flag
// that says why, and nothing else (never a NaN where a number is expected: the flag marks it).
//
// A calibration with a model extension (core/model_extension.hpp) is applied as offline
// (calibration/compensation.cpp), its terms evaluated on the scan's covariates
// (covariates_at_scan): the scan's bias gains the bias terms, and every window tests d under the
// extended mixture, each range with the scan's noise state and its modes' offset shifts. A range
// the outlier component takes (P > 0.5) is flagged kBeamOutlier.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "core/calibration.hpp"
#include "core/sliding_window_estimator.hpp"
#include "ipc/compensated_scan.hpp"
#include "realtime/junction_tracker.hpp"
#include "realtime/raw_scan.hpp"

namespace tofcomp::realtime {

// The node of a junction lag (core/covariate_table.hpp) in real time: a first-order low-pass of
// the junction estimate, starting at the first estimate, with core::first_order_lag's step. It
// is advanced at every scan and at every case reading (ScanCompensator::advance_lags), so it
// follows the junction through a power-off gap, where there are no scans, as the offline
// history does; advanced at the scans alone it jumped a gap at the junction of the first scan
// after it, as if the junction had stood there throughout.
struct JunctionLag {
  double time_constant_s = 0.0;
  double node_c = 0.0;
  double last_time_s = 0.0;
  double last_junction_c = 0.0;
  bool started = false;
  void update(double time_s, double junction_c);
};

// The covariates of a scan at time_s (the pipeline's clock): the junction estimate's temperature,
// heating rate and time since power-on, the hours since the clock's origin, the ambient the
// junction filter ran at (the last ambient reading, or the calibration's where none came: the
// daemon has no ambient sensor, a replayed recording may log one) and the lags' nodes less the
// junction.
core::CovariatesAt covariates_at_scan(const core::Calibration& calibration, double time_s,
                                      const JunctionEstimate& junction,
                                      const std::vector<JunctionLag>& lags);

class ScanCompensator {
 public:
  explicit ScanCompensator(core::SlidingWindowOptions window = {});

  // A new calibration (id > 0, increasing): every beam's window restarts under its modes.
  // Throws core::InvalidInput when the model is invalid or has more modes than the published
  // record carries (ipc::kMaxModes).
  void set_calibration(std::shared_ptr<const core::Calibration> calibration, std::uint32_t id);
  void clear_calibration();
  // New window settings: every window restarts.
  void set_window_options(const core::SlidingWindowOptions& window);
  const core::Calibration* calibration() const { return calibration_.get(); }

  // sequence: the published scan counter. Throws core::InvalidInput when ranges_mm and no_echo
  // differ in length or a range with an echo is not finite.
  ipc::CompensatedScan compensate(const RawScan& scan, const JunctionEstimate& junction,
                                  std::uint64_t sequence);
  // The junction estimate between scans (at a case reading): the lags' nodes follow it.
  void advance_lags(double time_s, const JunctionEstimate& junction);

 private:
  void rebuild_windows(std::size_t beams);

  core::SlidingWindowOptions window_options_;
  std::shared_ptr<const core::Calibration> calibration_;
  std::uint32_t calibration_id_ = 0;
  core::ExtendedMixture extended_mixture_;             // the calibration's (extended) mixture
  bool mode_shifts_ = false;                           // its extension moves a mode's offset
  std::vector<JunctionLag> lags_;                      // one per lag its terms read
  std::vector<core::SlidingWindowEstimator> windows_;  // one per beam, when calibrated
};

}  // namespace tofcomp::realtime
