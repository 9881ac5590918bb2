#include "daemon/compensation_inputs.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <filesystem>
#include <utility>

#include "core/error.hpp"
#include "daemon/plausible_calibration.hpp"
#include "io/calibration_file.hpp"
#include "settings/pipeline_setup.hpp"

namespace tofcomp::daemon {

CompensationInputs::CompensationInputs(const settings::DaemonConfig& config, EventClock& clock,
                                       Recordings& recordings)
    : clock_(clock), recordings_(recordings), pipeline_(settings::pipeline_settings(config)) {
  const bool missing =
      !config.calibration.file.empty() && !std::filesystem::exists(config.calibration.file);
  if (missing && config.recalibration.trigger == settings::RecalibrationTrigger::AtStartIfMissing) {
    spdlog::warn("calibration {} missing: recalibrating at start",
                 config.calibration.file.string());
    use_calibration(nullptr, "none");
  } else {
    use_calibration(read_plausible_calibration(config),
                    config.calibration.file.string());
  }
}

void CompensationInputs::use_calibration(std::shared_ptr<const core::Calibration> calibration,
                                         const std::string& source) {
  if (!calibration) {
    if (calibration_id_ != 0) pipeline_.clear_calibration();
    calibration_source_ = "none";
    spdlog::warn("no calibration configured: publishing raw ranges, flagged uncalibrated");
    return;
  }
  // The very calibration in use (a reload that changes nothing): no swap, the windows go on.
  if (const core::Calibration* in_use = pipeline_.calibration();
      in_use != nullptr && source == calibration_source_ &&
      io::calibration_to_yaml(*in_use) == io::calibration_to_yaml(*calibration)) {
    spdlog::info("calibration {} from {} unchanged: kept, its windows go on", calibration_id_,
                 source);
    return;
  }
  pipeline_.set_calibration(std::move(calibration), calibration_id_ + 1);
  ++calibration_id_;
  ++counters_.calibrations_swapped;
  calibration_source_ = source;
  const core::Calibration* in_use = pipeline_.calibration();
  spdlog::info("calibration {} in use, from {}{}", calibration_id_, source,
               in_use && in_use->extension
                   ? ", with the " + in_use->extension->name() + " extension"
                   : std::string());
}

void CompensationInputs::set_settings(const settings::DaemonConfig& config) {
  pipeline_.set_settings(settings::pipeline_settings(config));
}

void CompensationInputs::case_reading(double time_s, double case_c) {
  const double t = clock_.event_at(time_s);
  last_case_reading_ = {t, case_c};
  pipeline_.on_case_reading(t, case_c);
  recordings_.case_reading(t, case_c);
}

void CompensationInputs::power(double time_s, bool on) {
  if (power_on_ == on) return;
  power_on_ = on;
  ++counters_.power_changes;
  const double t = clock_.event_at(time_s);
  pipeline_.on_power(t, on);
  recordings_.power(t, on);
  spdlog::info("scanner power {}", on ? "on" : "off");
}

void CompensationInputs::switched(double time_s, bool on) {
  switched_off_ = !on;
  power(time_s, on);
}

std::optional<ipc::CompensatedScan> CompensationInputs::scan(ArrivedScan scan) {
  ++counters_.scans_in;
  const double t =
      clock_.scan_at(scan.recorded_time_s ? *scan.recorded_time_s : clock_.seconds(scan.received));
  scan.raw.time_s = t;
  // A scan proves the scanner is powered, whatever the last sense said; but one that reaches
  // the loop after the daemon switched the power off was measured before: it is published, and
  // left out of the recordings (measured data hold no range while the power is 0).
  const bool measured_before_switch_off = power_on_ == false && switched_off_;
  if (power_on_ == false && !switched_off_) power(t, true);
  std::optional<ipc::CompensatedScan> out;
  try {
    out = pipeline_.on_scan(scan.raw);
  } catch (const core::Error& e) {
    ++counters_.scans_rejected;
    refusal_ = e.what();
    if (const auto passed_over =
            refusal_reports_.report(std::chrono::steady_clock::now(), *refusal_)) {
      spdlog::error("scan {} not published: {}{}", scan.sequence, *refusal_,
                    *passed_over > 0
                        ? fmt::format(" ({} scans refused since the last report)",
                                      *passed_over + 1)
                        : std::string());
    }
    return std::nullopt;
  }
  refusal_.reset();
  if (!measured_before_switch_off) recordings_.scan(scan.raw);
  return out;
}

void CompensationInputs::seed(Recorder& recorder) const {
  if (last_case_reading_)
    recorder.case_reading(last_case_reading_->first, last_case_reading_->second);
  if (power_on_) recorder.power(clock_.last_event_s(), *power_on_);
}

}  // namespace tofcomp::daemon
