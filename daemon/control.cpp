#include "daemon/control.hpp"

#include <spdlog/spdlog.h>

#include <cmath>
#include <exception>
#include <utility>

#include "daemon/plausible_calibration.hpp"
#include "io/calibration_file.hpp"
#include "settings/pipeline_setup.hpp"

namespace tofcomp::daemon {

namespace {

// A NaN never reaches a client: JSON gets null.
nlohmann::json number_or_null(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

// The effect the calibration's model extension models (its extension.effect), or null.
nlohmann::json extension_in_use(const core::Calibration* calibration) {
  if (!calibration || !calibration->extension) return nullptr;
  return calibration->extension->name();
}

}  // namespace

const ipc::CompensatedScan* Control::latest_scan() {
  return modules_.outputs.latest();
}

nlohmann::json Control::status() {
  const CompensationInputs& inputs = modules_.inputs;
  nlohmann::json s;
  s["state"] = modules_.service.text();
  s["config"] = modules_.config.name();
  s["uptime_s"] = modules_.clock.now_s();
  s["link"] = modules_.link.state();
  s["device"] = modules_.link.device();
  s["case_sensor"] = {{"backend", modules_.sensor.describe()}, {"state", modules_.sensor.state()}};
  const std::optional<bool> power_on = inputs.power_on();
  s["power"] = power_on ? nlohmann::json(*power_on ? "on" : "off") : nlohmann::json("unknown");
  s["calibration"] = {{"id", inputs.calibration_id()},
                      {"source", inputs.calibration_source()},
                      {"extension", extension_in_use(inputs.calibration())}};
  s["recalibration"] = modules_.recalibration.state();
  if (const auto pid = modules_.recalibration.training_pid()) s["training_pid"] = *pid;
  if (nlohmann::json run = modules_.recalibration.run_status(); !run.is_null()) {
    s["calibration_run"] = std::move(run);
  }
  s["last_reload"] = last_reload_;
  s["recording"] = modules_.recordings.current_file();
  if (const ipc::CompensatedScan* latest = modules_.outputs.latest()) {
    s["latest"] = {{"sequence", latest->sequence},
                   {"timestamp_ns", latest->timestamp_ns},
                   {"junction_c", number_or_null(latest->junction_c)},
                   {"beams", latest->beams.size()}};
  }
  return s;
}

nlohmann::json Control::stats() {
  const auto& d = modules_.link.driver_counters();
  const InputCounters& in = modules_.inputs.counters();
  const SensorCounters& sensor = modules_.sensor.counters();
  nlohmann::json s;
  s["daemon"] = {{"scans_in", in.scans_in},
                 {"scans_published", modules_.outputs.scans_published()},
                 {"scans_rejected", in.scans_rejected},
                 {"readings_valid", sensor.readings_valid},
                 {"readings_invalid", sensor.readings_invalid},
                 {"power_changes", in.power_changes},
                 {"reloads", reloads_},
                 {"reloads_refused", reloads_refused_},
                 {"calibrations_swapped", in.calibrations_swapped},
                 {"recording_errors", modules_.recordings.errors()}};
  s["link"] = {{"scans", d.scans},
               {"rejected_scans", d.rejected_scans},
               {"naks", d.naks},
               {"timeouts", d.timeouts},
               {"link_losses", d.link_losses},
               {"stream_timeouts", d.stream_timeouts},
               {"device_resets", d.device_resets},
               {"restart_checks", d.restart_checks},
               {"bring_ups", d.bring_ups},
               {"rate_searches", d.rate_searches},
               {"crc_errors", d.decoder.crc_errors},
               {"garbage_bytes", d.decoder.garbage_bytes},
               {"truncated", d.decoder.truncated}};
  const ipc::ring::RingWriter& ring = modules_.outputs.ring();
  s["shm"] = {{"name", ring.name()}, {"published", ring.published()}};
  s["calibration"] = {{"id", modules_.inputs.calibration_id()},
                      {"extension", extension_in_use(modules_.inputs.calibration())}};
  if (const Recorder* recorder = modules_.recordings.configured()) {
    const auto& r = recorder->counters();
    s["recording"] = {
        {"rows", r.rows}, {"files", r.files}, {"scans", r.scans}, {"scans_lost", r.scans_lost}};
  }
  if (const auto e = modules_.link.device_counters()) {
    s["emulator"] = {{"scans_sent", e->scans_sent},
                     {"scans_skipped", e->scans_skipped},
                     {"telegrams_sent", e->telegrams_sent},
                     {"faults_injected", e->faults_injected}};
    nlohmann::json by_kind = nlohmann::json::object();
    for (const auto& [kind, count] : e->faults_by_kind) by_kind[kind] = count;
    s["emulator"]["faults_by_kind"] = std::move(by_kind);
  }
  return s;
}

socket::ReloadResult Control::reload() {
  modules_.service.reloading();
  RunningConfig& config = modules_.config;
  const std::string source = config.source();
  socket::ReloadResult result;
  try {
    // Everything that can fail is read before anything changes.
    settings::DaemonConfig next = config.read();
    auto calibration = read_plausible_calibration(next);
    const auto restart = settings::keys_needing_restart(config.current(), next);

    modules_.inputs.set_settings(next);
    modules_.inputs.use_calibration(std::move(calibration), next.calibration.file.string());
    spdlog::set_level(next.log.level);
    if (next.recording != config.current().recording) {
      modules_.recordings.configure(next.recording);
    }
    // Keys that need a restart keep their running values until then.
    config.apply(std::move(next));
    ++reloads_;
    result.ok = true;
    result.message = "reloaded " + source + "; calibration " +
                     std::to_string(modules_.inputs.calibration_id()) + " from " +
                     modules_.inputs.calibration_source();
    if (!restart.empty()) {
      std::string keys;
      for (const auto& k : restart) keys += (keys.empty() ? "" : ", ") + k;
      result.message += "; these changes take effect at the next restart: " + keys;
    }
  } catch (const std::exception& e) {
    ++reloads_refused_;
    result.ok = false;
    result.message = "reload of " + source + " refused, running on as before: " + e.what();
  }
  last_reload_ = result.message;
  modules_.service.reloaded();
  return result;
}

socket::RecalibrationResult Control::recalibrate(const nlohmann::json& args) {
  return modules_.recalibration.request(args);
}

}  // namespace tofcomp::daemon
