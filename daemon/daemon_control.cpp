// The daemon's answers to its clients and operators: status and statistics, reloading the
// configuration (SIGHUP or the socket's reload), and recalibration in the worker thread.
#include <spdlog/spdlog.h>

#include <cmath>

#include "calibration/measured_data_reader.hpp"
#include "calibration/training.hpp"
#include "core/error.hpp"
#include "daemon/daemon.hpp"
#include "io/datasheet_file.hpp"
#include "settings/daemon_config_yaml.hpp"
#include "settings/embedded_default_config.hpp"
#include "settings/pipeline_setup.hpp"

namespace tofcomp::daemon {

using Clock = std::chrono::steady_clock;

namespace {

// A NaN never reaches a client: JSON gets null.
nlohmann::json number_or_null(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

// The effect the calibration's model extension models (its extension.effect), or null.
nlohmann::json extension_in_use(const core::Calibration* calibration) {
  if (!calibration || !calibration->extension) return nullptr;
  return io::effect_token(calibration->extension->effect);
}

}  // namespace

nlohmann::json Daemon::status() {
  nlohmann::json s;
  s["state"] = status_text_;
  s["config"] = config_file_.empty() ? "built-in default" : config_file_.string();
  s["uptime_s"] = now_s(Clock::now());
  s["link"] = link_state_;
  s["device"] = emulator_ ? "emulated LMS 200 (" + config_.emulator.scenario.string() + ")"
                          : config_.link.device.string();
  s["case_sensor"] = {
      {"backend", sensor_ ? sensor_->describe()
                          : "recorded case readings (" + config_.emulator.recording.string() + ")"},
      {"state", sensor_state_}};
  s["power"] = power_on_ ? nlohmann::json(*power_on_ ? "on" : "off") : nlohmann::json("unknown");
  s["calibration"] = {{"id", calibration_id_},
                      {"source", calibration_source_},
                      {"extension", extension_in_use(pipeline_.calibration())}};
  s["recalibration"] = recalibration_state_;
  if (run_) s["calibration_run"] = calibration_run_status();
  s["last_reload"] = last_reload_;
  s["recording"] = recorder_ ? recorder_->current_file().string() : "off";
  if (latest_) {
    s["latest"] = {{"sequence", latest_->sequence},
                   {"timestamp_ns", latest_->timestamp_ns},
                   {"junction_c", number_or_null(latest_->junction_c)},
                   {"beams", latest_->beams.size()}};
  }
  return s;
}

nlohmann::json Daemon::stats() {
  const auto& d = driver_->counters();
  nlohmann::json s;
  s["daemon"] = {{"scans_in", counters_.scans_in},
                 {"scans_published", counters_.scans_published},
                 {"scans_rejected", counters_.scans_rejected},
                 {"readings_valid", counters_.readings_valid},
                 {"readings_invalid", counters_.readings_invalid},
                 {"power_changes", counters_.power_changes},
                 {"reloads", counters_.reloads},
                 {"reloads_refused", counters_.reloads_refused},
                 {"calibrations_swapped", counters_.calibrations_swapped},
                 {"recording_errors", counters_.recording_errors}};
  s["link"] = {{"scans", d.scans},
               {"rejected_scans", d.rejected_scans},
               {"naks", d.naks},
               {"timeouts", d.timeouts},
               {"link_losses", d.link_losses},
               {"stream_timeouts", d.stream_timeouts},
               {"device_resets", d.device_resets},
               {"bring_ups", d.bring_ups},
               {"rate_searches", d.rate_searches},
               {"crc_errors", d.decoder.crc_errors},
               {"garbage_bytes", d.decoder.garbage_bytes},
               {"truncated", d.decoder.truncated}};
  s["shm"] = {{"name", ring_->name()}, {"published", ring_->published()}};
  s["calibration"] = {{"id", calibration_id_},
                      {"extension", extension_in_use(pipeline_.calibration())}};
  if (recorder_) {
    const auto& r = recorder_->counters();
    s["recording"] = {{"rows", r.rows}, {"files", r.files}, {"scans", r.scans}};
  }
  if (emulator_) {
    const auto e = emulator_->counters();
    s["emulator"] = {{"scans_sent", e.scans_sent},
                     {"scans_skipped", e.scans_skipped},
                     {"telegrams_sent", e.telegrams_sent},
                     {"faults_injected", e.injected.total()}};
  }
  return s;
}

socket::ReloadResult Daemon::reload() {
  notifier_.reloading();
  const std::string source = config_file_.empty() ? "the built-in default" : config_file_.string();
  socket::ReloadResult result;
  try {
    // Everything that can fail is read before anything changes.
    settings::DaemonConfig next = config_file_.empty() ? settings::embedded_default_config()
                                                       : settings::load_daemon_config(config_file_);
    auto calibration = settings::read_configured_calibration(next);
    const auto restart = settings::keys_needing_restart(config_, next);

    pipeline_.set_settings(settings::pipeline_settings(next));
    use_calibration(std::move(calibration), next.calibration.file.string());
    spdlog::set_level(next.log.level);
    if (next.recording != config_.recording) {
      recorder_.reset();
      if (next.recording.enabled) {
        recorder_ = std::make_unique<Recorder>(RecorderSettings{
            next.recording.directory, next.recording.max_rows, next.recording.max_minutes});
      }
    }
    // Keys that need a restart keep their running values until then.
    settings::DaemonConfig applied = next;
    applied.link = config_.link;
    applied.emulator = config_.emulator;
    applied.case_sensor = config_.case_sensor;
    applied.power = config_.power;
    applied.outputs = config_.outputs;
    config_ = std::move(applied);
    ++counters_.reloads;
    result.ok = true;
    result.message = "reloaded " + source + "; calibration " + std::to_string(calibration_id_) +
                     " from " + calibration_source_;
    if (!restart.empty()) {
      std::string keys;
      for (const auto& k : restart) keys += (keys.empty() ? "" : ", ") + k;
      result.message += "; these changes take effect at the next restart: " + keys;
    }
  } catch (const std::exception& e) {
    ++counters_.reloads_refused;
    result.ok = false;
    result.message = "reload of " + source + " refused, running on as before: " + e.what();
  }
  last_reload_ = result.message;
  notifier_.ready();
  return result;
}

socket::RecalibrationResult Daemon::recalibrate(const nlohmann::json& args) {
  std::filesystem::path data = config_.recalibration.data;
  for (const auto& [key, value] : args.items()) {
    if (key != "recording") {
      throw core::InvalidInput("args." + key + ": unknown; the one argument is recording");
    }
    if (!value.is_string() || value.get<std::string>().empty()) {
      throw core::InvalidInput("args.recording: expected the path of a recording (a string)");
    }
    data = value.get<std::string>();
    // As in the configuration: a relative path is taken from the configuration's directory.
    if (data.is_relative() && !config_file_.empty()) data = config_file_.parent_path() / data;
  }
  socket::RecalibrationResult r;
  if (worker_running_ || (run_ && run_->running())) {
    r.message = "a recalibration is already running: " + recalibration_state_;
    return r;
  }
  switch (config_.recalibration.source) {
    case settings::RecalibrationSource::None:
      r.message = "recalibration.source is none in " + config_.source +
                  ": set it to recording (and recalibration.recording.data) or power_cycle_run "
                  "to recalibrate";
      return r;
    case settings::RecalibrationSource::Recording:
      break;
    case settings::RecalibrationSource::PowerCycleRun:
      if (!args.empty()) {
        r.message =
            "args.recording applies to recalibration.source recording; the source is "
            "power_cycle_run, which records its own";
        return r;
      }
      r.message = start_power_cycle_run();
      r.accepted = r.message.empty();
      if (r.accepted) r.message = recalibration_state_;
      return r;
  }
  if (data.empty()) {
    r.message = "no recording to train on: set recalibration.recording.data or pass args.recording";
    return r;
  }
  start_recalibration(data, 0);
  r.accepted = true;
  r.message = recalibration_state_;
  return r;
}

// Trains on `beam` of `data` in the worker thread (§3 thermal identification, §5 EM), writes
// the calibration atomically, and leaves the outcome for finish_recalibration() on the loop.
void Daemon::start_recalibration(std::filesystem::path data, int beam) {
  const std::filesystem::path output = config_.recalibration.output.empty()
                                           ? config_.calibration.file
                                           : config_.recalibration.output;
  const std::filesystem::path datasheet = config_.recalibration.datasheet;
  recalibration_state_ = "training on " + data.string() + ", writing " + output.string();
  spdlog::info("recalibration: {}", recalibration_state_);
  worker_running_ = true;
  worker_ = std::thread([this, data, beam, output, datasheet] {
    RecalibrationOutcome outcome;
    outcome.file = output;
    try {
      if (output.empty()) throw core::Error("no calibration file to write (calibration.file)");
      std::vector<std::string> warnings;
      const calibration::MeasuredData measured =
          calibration::read_measured_data(data.string(), beam, warnings);
      calibration::TrainSettings settings;
      settings.thermal.datasheet = io::read_datasheet_file(datasheet.string());
      const calibration::Training trained = calibration::train_calibration(measured, settings);
      io::write_calibration_file(output.string(), trained.calibration);
      outcome.calibration = std::make_shared<const core::Calibration>(trained.calibration);
    } catch (const std::exception& e) {
      outcome.error = e.what();
    }
    std::lock_guard lock(outcome_mutex_);
    outcome_ = std::move(outcome);
  });
}

void Daemon::finish_recalibration() {
  std::optional<RecalibrationOutcome> outcome;
  {
    std::lock_guard lock(outcome_mutex_);
    outcome.swap(outcome_);
  }
  if (!outcome) return;
  worker_.join();
  worker_running_ = false;
  if (!outcome->error.empty()) {
    recalibration_state_ = "failed: " + outcome->error;
    spdlog::error("recalibration {}", recalibration_state_);
    return;
  }
  try {
    use_calibration(outcome->calibration, outcome->file.string());
    recalibration_state_ =
        "done: calibration " + std::to_string(calibration_id_) + " from " + outcome->file.string();
    spdlog::info("recalibration {}", recalibration_state_);
  } catch (const core::Error& e) {
    recalibration_state_ = std::string("failed: ") + e.what();
    spdlog::error("recalibration {}", recalibration_state_);
  }
}

}  // namespace tofcomp::daemon
