// The daemon's compensation path as one object, fed events in arrival order: case readings,
// power changes and scans. tofcompd feeds it live; replay_recording (realtime/recording_replay.hpp)
// feeds it a recording's rows, so that the two give the same outputs for the same events.
// A calibration's model extension is applied by the scan compensator, with the junction
// tracker's heating rate or time since power-on for an extension whose covariate it is.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>

#include "realtime/junction_tracker.hpp"
#include "realtime/scan_compensator.hpp"

namespace tofcomp::realtime {

struct PipelineSettings {
  core::SlidingWindowOptions window{.window = 200,
                                    .min_samples = 10,
                                    .method = core::WindowEm::Incremental,
                                    .em = {},
                                    .refreshes = 4,
                                    .change = {}};
  JunctionTrackerSettings junction;
  bool operator==(const PipelineSettings&) const = default;
};

class CompensationPipeline {
 public:
  explicit CompensationPipeline(PipelineSettings settings = {});

  // Swaps the calibration in between two scans (id > 0, increasing): the junction filter
  // restarts on the new thermal model from the last case reading, every window restarts.
  // Throws core::InvalidInput for a model the pipeline cannot use; the old one then stays.
  void set_calibration(std::shared_ptr<const core::Calibration> calibration, std::uint32_t id);
  // Back to publishing raw ranges, flagged uncalibrated.
  void clear_calibration();
  // New settings (a reload): windows restart; the junction filter keeps its state unless its
  // settings changed. Settings equal to those in force change nothing.
  void set_settings(const PipelineSettings& settings);

  void on_case_reading(double time_s, double case_c);
  void on_power(double time_s, bool on);
  // An ambient reading (a recording's ambient_c): the junction filter runs at it from then on,
  // and an ambient term reads it; without one, both use the calibration's ambient.
  void on_ambient(double time_s, double ambient_c);
  // The scan compensated, numbered from 0 without gaps.
  ipc::CompensatedScan on_scan(const RawScan& scan);

  const core::Calibration* calibration() const { return compensator_.calibration(); }
  std::uint64_t scans() const { return next_sequence_; }

 private:
  void restart_tracker();

  PipelineSettings settings_;
  ScanCompensator compensator_;
  std::shared_ptr<const core::Calibration> calibration_;
  std::optional<JunctionTracker> tracker_;
  std::optional<std::pair<double, double>> last_reading_;  // time_s, case_c
  std::optional<std::pair<double, bool>> power_;           // time_s of the last change, state
  std::optional<double> last_switch_on_s_;
  std::optional<std::pair<double, double>> ambient_;  // time_s, ambient_c of the last
  std::uint64_t next_sequence_ = 0;
};

}  // namespace tofcomp::realtime
