// The compensation pipeline (realtime/compensation_pipeline.hpp) and what it is fed, in the order
// of the event clock: the case readings, the scanner's power (as sensed, or as the daemon
// switched it), the scans; each input goes to the recordings as the pipeline took it. Owns the
// pipeline, the calibration in use (its id and source), the power state, the last case reading,
// and the counts of scans in and rejected, power changes and calibration swaps.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "core/calibration.hpp"
#include "daemon/arrived_scan.hpp"
#include "daemon/event_clock.hpp"
#include "daemon/recorder.hpp"
#include "daemon/recordings.hpp"
#include "daemon/report_throttle.hpp"
#include "ipc/compensated_scan.hpp"
#include "realtime/compensation_pipeline.hpp"
#include "settings/daemon_config.hpp"

namespace tofcomp::daemon {

// Refusals for one reason are logged at most this often (a broken path refuses every scan,
// 75 a second).
inline constexpr std::chrono::seconds kRefusalReportInterval{10};

struct InputCounters {
  std::uint64_t scans_in = 0;        // from the link
  std::uint64_t scans_rejected = 0;  // scans the pipeline refused (logged)
  std::uint64_t power_changes = 0;
  std::uint64_t calibrations_swapped = 0;
};

class CompensationInputs {
 public:
  // Takes the configured calibration, or none when its file is missing and recalibration runs
  // at start then. Throws core::Error naming the calibration file when it cannot be read.
  CompensationInputs(const settings::DaemonConfig& config, EventClock& clock,
                     Recordings& recordings);

  // Swaps a calibration in (on the loop, between two scans: no scan is lost or mixed); null:
  // none, ranges are published raw. The very calibration in use, from the same source, is kept
  // as it is (its id and its windows), so that a reload that changes nothing restarts nothing.
  void use_calibration(std::shared_ptr<const core::Calibration> calibration,
                       const std::string& source);
  // The pipeline's settings from a reloaded configuration.
  void set_settings(const settings::DaemonConfig& config);

  void case_reading(double time_s, double case_c);
  // The power as sensed (or as a recording or the emulated supply has it).
  void power(double time_s, bool on);
  // The daemon switched the scanner's power (a calibration run): while it is off, the link's
  // silence is expected.
  void switched(double time_s, bool on);
  bool switched_off() const { return switched_off_; }
  // The scan compensated, or nullopt when the pipeline refused it: logged, the first of a run
  // of refusals for one reason and then at most once per kRefusalReportInterval with the count.
  std::optional<ipc::CompensatedScan> scan(ArrivedScan scan);
  // Why the last scan was refused; nullopt when it was not.
  const std::optional<std::string>& refusal() const { return refusal_; }

  // Starts a recording with the state the pipeline is in: the last case reading, the power.
  void seed(Recorder& recorder) const;

  std::optional<bool> power_on() const { return power_on_; }
  std::uint32_t calibration_id() const { return calibration_id_; }
  const std::string& calibration_source() const { return calibration_source_; }
  const core::Calibration* calibration() const { return pipeline_.calibration(); }
  const InputCounters& counters() const { return counters_; }

 private:
  EventClock& clock_;
  Recordings& recordings_;
  realtime::CompensationPipeline pipeline_;
  std::uint32_t calibration_id_ = 0;
  std::string calibration_source_ = "none";
  std::optional<bool> power_on_;
  bool switched_off_ = false;                                   // the daemon switched it off
  std::optional<std::pair<double, double>> last_case_reading_;  // time_s, °C
  InputCounters counters_;
  std::optional<std::string> refusal_;  // of the last scan
  ReportThrottle refusal_reports_{kRefusalReportInterval};
};

}  // namespace tofcomp::daemon
