#include "realtime/compensation_pipeline.hpp"

#include <cmath>

#include "core/error.hpp"

namespace tofcomp::realtime {

CompensationPipeline::CompensationPipeline(PipelineSettings settings)
    : settings_(settings), compensator_(settings.window) {}

void CompensationPipeline::restart_tracker() {
  tracker_.reset();
  if (!calibration_) return;
  tracker_.emplace(*calibration_, settings_.junction);
  if (power_) tracker_->set_power(power_->first, power_->second);
  if (ambient_) tracker_->set_ambient(ambient_->first, ambient_->second);
  if (last_switch_on_s_) tracker_->set_last_switch_on(*last_switch_on_s_);
  if (last_reading_) tracker_->add_case_reading(last_reading_->first, last_reading_->second);
}

void CompensationPipeline::set_calibration(std::shared_ptr<const core::Calibration> calibration,
                                           std::uint32_t id) {
  JunctionTracker check(*calibration, settings_.junction);  // throws before anything changes
  compensator_.set_calibration(calibration, id);
  calibration_ = std::move(calibration);
  restart_tracker();
}

void CompensationPipeline::clear_calibration() {
  compensator_.clear_calibration();
  calibration_.reset();
  tracker_.reset();
}

void CompensationPipeline::set_settings(const PipelineSettings& settings) {
  if (settings == settings_) return;  // nothing changes: the windows go on
  compensator_.set_window_options(settings.window);
  const bool junction_changed = !(settings.junction == settings_.junction);
  settings_ = settings;
  if (junction_changed) restart_tracker();
}

void CompensationPipeline::on_case_reading(double time_s, double case_c) {
  last_reading_ = {time_s, case_c};
  if (!tracker_) return;
  tracker_->add_case_reading(time_s, case_c);
  compensator_.advance_lags(time_s, tracker_->at(time_s));
}

void CompensationPipeline::on_power(double time_s, bool on) {
  if (on && !(power_ ? power_->second : true)) last_switch_on_s_ = time_s;
  power_ = {time_s, on};
  if (tracker_) tracker_->set_power(time_s, on);
}

void CompensationPipeline::on_ambient(double time_s, double ambient_c) {
  if (!std::isfinite(time_s) || !std::isfinite(ambient_c)) {
    throw core::InvalidInput("an ambient reading must be finite");
  }
  if (tracker_) tracker_->set_ambient(time_s, ambient_c);
  ambient_ = {time_s, ambient_c};
}

ipc::CompensatedScan CompensationPipeline::on_scan(const RawScan& scan) {
  const JunctionEstimate junction = tracker_ ? tracker_->at(scan.time_s) : JunctionEstimate{};
  ipc::CompensatedScan out = compensator_.compensate(scan, junction, next_sequence_);
  ++next_sequence_;
  return out;
}

}  // namespace tofcomp::realtime
