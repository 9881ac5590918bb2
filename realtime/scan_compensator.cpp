#include "realtime/scan_compensator.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "core/error.hpp"

namespace tofcomp::realtime {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

core::CovariatesAt covariates_at_scan(const core::Calibration& calibration, double time_s,
                                      const JunctionEstimate& junction,
                                      const std::vector<JunctionLag>& lags) {
  core::CovariatesAt at;
  at.junction_c = junction.junction_c;
  at.heating_rate_c_per_min = junction.heating_rate_c_per_min;
  at.time_since_power_on_s = junction.time_since_power_on_s;
  at.time_h = time_s / 3600.0;
  at.ambient_c = junction.valid ? junction.ambient_c : calibration.ambient_c;
  for (const JunctionLag& lag : lags) {
    at.junction_lag_c.emplace_back(lag.time_constant_s, lag.node_c - junction.junction_c);
  }
  return at;
}

void JunctionLag::update(double time_s, double junction_c) {
  if (!started) {
    node_c = junction_c;
    started = true;
  } else if (time_s > last_time_s) {
    // core::first_order_lag's step: the junction taken as the mean of the step's two ends.
    const double input = 0.5 * (junction_c + last_junction_c);
    node_c = input + std::exp(-(time_s - last_time_s) / time_constant_s) * (node_c - input);
  } else {
    return;  // a late estimate: the node has moved past it
  }
  last_time_s = time_s;
  last_junction_c = junction_c;
}

ScanCompensator::ScanCompensator(core::SlidingWindowOptions window) : window_options_(window) {}

void ScanCompensator::advance_lags(double time_s, const JunctionEstimate& junction) {
  if (!junction.valid) return;
  for (JunctionLag& lag : lags_) lag.update(time_s, junction.junction_c);
}

void ScanCompensator::set_calibration(std::shared_ptr<const core::Calibration> calibration,
                                      std::uint32_t id) {
  if (!calibration) throw core::InvalidInput("scan compensator: no calibration given");
  calibration->model.validate();
  if (calibration->model.mixture.modes() > ipc::kMaxModes) {
    throw core::InvalidInput(
        "calibration has " + std::to_string(calibration->model.mixture.modes()) +
        " lasing modes; the published record carries at most " + std::to_string(ipc::kMaxModes));
  }
  lags_.clear();
  if (calibration->extension) {
    calibration->extension->validate();
    for (const double tau : calibration->extension->lag_time_constants()) {
      lags_.push_back(JunctionLag{tau});
    }
    if (calibration->extension->extended_mixture.modes.modes() > ipc::kMaxModes) {
      throw core::InvalidInput(
          "calibration extension has " +
          std::to_string(calibration->extension->extended_mixture.modes.modes()) +
          " lasing modes; the published record carries at most " + std::to_string(ipc::kMaxModes));
    }
  }
  core::ExtendedMixture mixture = core::compensation_mixture(*calibration);
  const bool mode_shifts = calibration->extension && calibration->extension->has_mode_shift();
  // Checks the window options against this mixture before anything changes.
  core::SlidingWindowEstimator check(mixture, window_options_, mode_shifts);
  extended_mixture_ = std::move(mixture);
  mode_shifts_ = mode_shifts;
  calibration_ = std::move(calibration);
  calibration_id_ = id;
  windows_.clear();
}

void ScanCompensator::clear_calibration() {
  calibration_.reset();
  calibration_id_ = 0;
  windows_.clear();
}

void ScanCompensator::set_window_options(const core::SlidingWindowOptions& window) {
  if (calibration_) core::SlidingWindowEstimator check(extended_mixture_, window, mode_shifts_);
  window_options_ = window;
  windows_.clear();
}

void ScanCompensator::rebuild_windows(std::size_t beams) {
  windows_.clear();
  windows_.reserve(beams);
  for (std::size_t b = 0; b < beams; ++b) {
    windows_.emplace_back(extended_mixture_, window_options_, mode_shifts_);
  }
}

ipc::CompensatedScan ScanCompensator::compensate(const RawScan& scan,
                                                 const JunctionEstimate& junction,
                                                 std::uint64_t sequence) {
  const std::size_t beams = scan.ranges_mm.size();
  if (scan.no_echo.size() != beams) {
    throw core::InvalidInput("scan " + std::to_string(scan.device_sequence) + ": " +
                             std::to_string(beams) + " ranges but " +
                             std::to_string(scan.no_echo.size()) + " echo flags");
  }
  ipc::CompensatedScan out;
  out.sequence = sequence;
  out.device_sequence = scan.device_sequence;
  out.timestamp_ns = scan.timestamp_ns;
  out.rays = scan.rays;
  out.start_angle_deg = scan.start_angle_deg;
  out.resolution_deg = scan.resolution_deg;
  out.calibration_id = calibration_id_;
  out.junction_c = junction.valid ? junction.junction_c : kNaN;
  out.junction_std_c = junction.valid ? junction.junction_std_c : kNaN;
  out.case_c = junction.valid ? junction.case_c : kNaN;
  out.beams.resize(beams);

  const bool calibrated = calibration_ != nullptr;
  const bool compensating = calibrated && junction.valid;
  std::uint16_t scan_flags = 0;
  if (!calibrated) scan_flags |= ipc::kBeamUncalibrated;
  if (!junction.valid || junction.stale) scan_flags |= ipc::kBeamTemperatureStale;
  if (compensating && calibration_->model.extrapolates(junction.junction_c)) {
    scan_flags |= ipc::kBeamTemperatureExtrapolated;
  }
  if (compensating && windows_.size() != beams) rebuild_windows(beams);
  // Eq. 8: the bias H(t̂^j)θ̂ (and an extension's bias terms) is one value for the whole scan, and
  // so are the noise state and the modes' offset shifts.
  double bias = 0.0;
  int state = 0;
  Eigen::VectorXd shift;
  if (compensating) {
    bias = calibration_->model.bias_at(junction.junction_c);
    if (calibration_->extension) {
      for (JunctionLag& lag : lags_) lag.update(scan.time_s, junction.junction_c);
      const core::CovariatesAt at =
          covariates_at_scan(*calibration_, scan.time_s, junction, lags_);
      bias += calibration_->extension->bias_at(at);
      state = calibration_->extension->state_at(at);
      if (mode_shifts_) shift = calibration_->extension->mode_shift_at(at);
    }
  }
  const core::MixtureParameters* modes = calibrated ? &extended_mixture_.modes : nullptr;

  for (std::size_t b = 0; b < beams; ++b) {
    ipc::BeamValue& v = out.beams[b];
    v.flags = scan_flags;
    v.mode_count = modes ? static_cast<std::uint8_t>(modes->modes()) : 0;
    v.compensated_mm = kNaN;
    v.window_mm = kNaN;
    v.window_std_mm = kNaN;
    if (scan.no_echo[b]) {
      v.raw_mm = kNaN;
      v.flags |= ipc::kBeamNoEcho;
      continue;
    }
    const double y = scan.ranges_mm[b];
    if (!std::isfinite(y)) {
      throw core::InvalidInput("scan " + std::to_string(scan.device_sequence) + ", beam " +
                               std::to_string(b) + ": range is not finite");
    }
    v.raw_mm = y;
    if (!compensating) continue;
    const double corrected = y - bias;
    const core::WindowEstimate e = windows_[b].add(corrected, state, shift);
    v.most_probable_mode = static_cast<std::uint8_t>(e.most_probable_mode);
    for (int i = 0; i < modes->modes(); ++i) {
      v.mode_posterior[static_cast<std::size_t>(i)] = static_cast<float>(e.posterior[i]);
    }
    v.compensated_mm = corrected - modes->mean[e.most_probable_mode] -
                       (mode_shifts_ ? shift[e.most_probable_mode] : 0.0);
    if (e.restarting) {
      v.flags |= ipc::kBeamWindowRestarting;
    } else {
      v.window_mm = e.distance;
      v.window_std_mm = e.distance_std;
    }
    if (e.change_detected) v.flags |= ipc::kBeamChangeDetected;
    if (e.outlier > 0.5) v.flags |= ipc::kBeamOutlier;
  }
  return out;
}

}  // namespace tofcomp::realtime
