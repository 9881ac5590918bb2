// The compensation of one scan, beam by beam (Eq. 8 and §6 in real time): each range y of a
// beam becomes y − H(t̂^j)θ̂ (the bias at the scan's junction temperature, one value for the
// whole scan), fed to the beam's sliding-window EM estimator (core/sliding_window_estimator.hpp)
// for d̂ and its standard deviation, and published compensated by its most probable mode:
// y − H(t̂^j)θ̂ − μ_î. Ranges with no echo are published as such and do not enter the window.
// Without a calibration or a junction temperature the raw ranges are published with the flag
// that says why, and nothing else (never a NaN where a number is expected: the flag marks it).
//
// A calibration with a model extension (core/model_extension.hpp) is applied as offline
// (calibration/compensation.cpp): the scan's bias gains γ·c, c the hours since the pipeline's clock
// origin (RawScan::time_s / 3600), the junction's heating rate or the warm-up exp(−t_on/τ) from the
// time since the last power-on (both in JunctionEstimate), and every window
// tests d under the extended mixture, each range with the temperature bin of the scan's junction
// estimate. A range the outlier component takes (P > 0.5) is flagged kBeamOutlier.
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

// γ·c of the calibration's extension for a scan at time_s (the pipeline's clock) with this
// junction estimate; 0 without an extension or a covariate.
double covariate_bias(const core::Calibration& calibration, double time_s,
                      const JunctionEstimate& junction);

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

 private:
  void rebuild_windows(std::size_t beams);

  core::SlidingWindowOptions window_options_;
  std::shared_ptr<const core::Calibration> calibration_;
  std::uint32_t calibration_id_ = 0;
  core::ExtendedMixture extended_mixture_;             // the calibration's (extended) mixture
  std::vector<core::SlidingWindowEstimator> windows_;  // one per beam, when calibrated
};

}  // namespace tofcomp::realtime
