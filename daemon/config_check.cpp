// The files of a configuration, loaded: see config_check.hpp.
#include "daemon/config_check.hpp"

#include <filesystem>

#include "core/error.hpp"
#include "daemon/plausible_calibration.hpp"
#include "io/calibration_file.hpp"
#include "io/checked_file.hpp"
#include "io/bundled_datasheet.hpp"
#include "io/datasheet_file.hpp"
#include "io/measured_data_csv.hpp"
#include "ipc/ring/ring_writer.hpp"
#include "settings/daemon_config_adapters.hpp"
#include "settings/pipeline_setup.hpp"

namespace tofcomp::daemon {

namespace {

constexpr std::uint64_t kMib = 1u << 20;

// Runs `load`; a failure becomes an error naming the configuration, the key and the file.
template <class Load>
void loads(const settings::DaemonConfig& config, const std::string& key,
           const std::filesystem::path& file, Load load) {
  try {
    load();
  } catch (const std::exception& e) {
    throw core::Error(config.source + ": " + key + " " + file.string() + ": " + e.what());
  }
}

// Measured data as recalibration or the emulator would take them: a checked regular file under
// the recording cap, read whole.
void read_measured_data(const std::filesystem::path& file, std::uint64_t max_bytes) {
  const io::CheckedFile checked =
      io::open_checked_file(file, max_bytes, "recording", "recalibration.limits.recording_mib");
  io::read_measured_data_file(file);
}

// The ring as the daemon makes it (daemon/scan_outputs.cpp), within its limits and the shared
// memory there is: one that is not would fail the daemon's start.
void check_ring(const settings::DaemonConfig& config) {
  try {
    ipc::ring::check_ring_fits(config.outputs.shm.name,
                               static_cast<std::uint32_t>(config.outputs.shm.slots),
                               ipc::ring::kDefaultMaxBeams);
  } catch (const core::Error& e) {
    throw core::Error(config.source + ": outputs.shm.slots " +
                      std::to_string(config.outputs.shm.slots) + ": " + e.what());
  }
}

}  // namespace

std::string check_configuration(const settings::DaemonConfig& config) {
  std::string loaded;
  const auto note = [&](const std::string& what) { loaded += "; " + what; };
  check_ring(config);
  const settings::RecalibrationConfig& recal = config.recalibration;
  const std::uint64_t recording_cap = recal.limits.recording_mib * kMib;

  if (!config.calibration.file.empty()) {
    const bool made_at_start = recal.trigger == settings::RecalibrationTrigger::AtStartIfMissing &&
                               !std::filesystem::exists(config.calibration.file);
    if (made_at_start) {
      note("calibration " + config.calibration.file.string() + " missing: made at start");
    } else {
      loads(config, "calibration.file", config.calibration.file, [&] {
        auto calibration = settings::read_configured_calibration(config);
        require_plausible(*calibration);
        realtime::CompensationPipeline pipeline(settings::pipeline_settings(config));
        pipeline.set_calibration(calibration, 1);
        note("calibration " + config.calibration.file.string() +
             (calibration->extension
                  ? " with the " + calibration->extension->name() + " extension"
                  : std::string()));
      });
    }
  }
  if (config.emulator.enabled) {
    // The scenario, loaded as the emulator takes it (its errors name emulator.scenario).
    settings::emulator_settings(config);
    note("scenario " + config.emulator.scenario.string());
    if (!config.emulator.recording.empty()) {
      loads(config, "emulator.recording", config.emulator.recording,
            [&] { read_measured_data(config.emulator.recording, recording_cap); });
      note("played recording " + config.emulator.recording.string());
    }
  }
  if (recal.source != settings::RecalibrationSource::None) {
    if (recal.datasheet.empty()) {
      note(std::string("datasheet: ") + io::kBundledDatasheetName);
    } else {
      loads(config, "recalibration.datasheet", recal.datasheet,
            [&] { io::read_datasheet_file(recal.datasheet.string()); });
      note("datasheet " + recal.datasheet.string());
    }
  }
  if (recal.source == settings::RecalibrationSource::Recording) {
    loads(config, "recalibration.recording.data", recal.data,
          [&] { read_measured_data(recal.data, recording_cap); });
    note("recording " + recal.data.string());
    if (!std::filesystem::is_directory(recal.recordings_directory)) {
      throw core::Error(config.source + ": recalibration.recording.directory " +
                        recal.recordings_directory.string() + ": not a directory");
    }
  }
  return "valid" + loaded;
}

}  // namespace tofcomp::daemon
