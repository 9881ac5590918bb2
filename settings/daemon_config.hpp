// tofcompd's configuration as plain values: one struct per section of tofcompd.yaml
// (docs/configuration.md documents every key, its default and its range). The YAML reader
// (settings/daemon_config_yaml.hpp) fills and checks it; validate() holds the rules that
// join several sections; keys_needing_restart() says which changes a reload cannot apply live.
#pragma once

#include <spdlog/common.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/kalman.hpp"
#include "core/sliding_window_estimator.hpp"
#include "hal/gpio/power_control.hpp"
#include "hal/lms2xx/commands.hpp"
#include "hal/lms2xx/measuring_mode.hpp"
#include "hal/sensors/sensor_config.hpp"
#include "ipc/socket/protocol_constants.hpp"
#include "ipc/socket/server_defaults.hpp"
#include "settings/log_settings.hpp"
#include "sim/lms200/fault_injector.hpp"

namespace tofcomp::settings {

// `link`: the serial link to the LMS 200 (the host driver's settings, hal/lms2xx/host_driver.hpp).
struct LinkConfig {
  // The serial port. Empty only while the emulator runs without a link path: the driver then
  // opens the emulator's own pty (sim::lms200::Emulator::device_path()).
  std::filesystem::path device;
  unsigned baud = 500000;
  hal::lms2xx::Variant variant{180, 50};
  hal::lms2xx::Units units = hal::lms2xx::Units::Millimetre;
  hal::lms2xx::MeasuringMode measuring_mode = hal::lms2xx::MeasuringMode::Range8m;
  std::chrono::milliseconds ack_timeout{60};
  std::chrono::milliseconds reply_timeout{200};
  std::chrono::milliseconds scan_timeout{1000};
  int attempts = 3;
  std::chrono::milliseconds backoff_initial{50};
  std::chrono::milliseconds backoff_max{2000};
  bool operator==(const LinkConfig&) const = default;
};

// `emulator`: an emulated LMS 200 served in-process on a pty, driven by a twin scenario.
struct EmulatorConfig {
  bool enabled = false;
  std::filesystem::path scenario;  // a twin scenario (docs/scenarios.md); required when enabled
  // A tofcompd recording to play instead of the twin (docs/daemon.md); empty: the twin. The
  // scenario still gives the device's identity and output.
  std::filesystem::path recording;
  double time_scale = 1.0;  // twin seconds per wall second; 0: as fast as the host reads
  sim::lms200::FaultRates faults;
  std::uint64_t fault_seed = 1;
  std::filesystem::path link;  // a stable symlink to the pty; empty: none
  bool rs232 = false;          // an RS-232 unit, which refuses 500 kBd
};

// `case_sensor`: the case thermometer (the paper's t^s) and its plausibility limits.
struct CaseSensorConfig {
  hal::SensorConfig sensor;  // sensor.limits.max_age is the key `stale_after_s`
  std::chrono::milliseconds poll_interval{1000};
};

// `power`: the scanner's power switch and power-sense GPIO lines, each optional.
struct PowerConfig {
  std::optional<hal::GpioLineConfig> power_switch;  // key `switch`
  std::optional<hal::GpioLineConfig> sense;
};

// `calibration.noise`: overrides of the Kalman noise levels the calibration file carries.
struct ThermalNoiseOverrides {
  std::optional<double> case_process_psd_k2_per_s;      // key process_noise_case_k2_per_s
  std::optional<double> junction_process_psd_k2_per_s;  // key process_noise_junction_k2_per_s
  std::optional<double> measurement_variance_k2;        // key sensor_noise_k2
  // The file's levels with the overrides given here put in their place.
  core::ThermalNoise applied_to(core::ThermalNoise from_file) const;
  bool operator==(const ThermalNoiseOverrides&) const = default;
};

// `calibration`: the calibration file (docs/calibration-file.md) compensation starts from.
struct CalibrationConfig {
  std::filesystem::path file;          // empty: no calibration; ranges are published uncompensated
  ThermalNoiseOverrides kalman_noise;  // key `noise`
  std::optional<double> ambient_c;     // overrides the file's ambient_c
};

// An inclusive range of beam indices.
struct BeamRange {
  int first = 0;
  int last = 0;
  bool operator==(const BeamRange&) const = default;
};

// `compensation`: the real-time window estimate of §6 on every beam.
struct CompensationConfig {
  core::SlidingWindowOptions window;
};

// `outputs.socket`: the Unix socket of JSON lines. The defaults are the socket server's own
// (ipc/socket/server_defaults.hpp); the path is the system's, and the reader puts who runs's
// (ipc/default_places.hpp).
struct SocketOutputConfig {
  std::filesystem::path path = ipc::socket::kDefaultSocketPath;
  unsigned mode = ipc::socket::kDefaultSocketMode;
  int max_clients = static_cast<int>(ipc::socket::kDefaultMaxClients);
  std::size_t max_request_bytes = ipc::socket::kDefaultMaxRequestBytes;
  std::size_t max_queued_bytes_per_client = ipc::socket::kDefaultMaxQueuedBytesPerClient;
  std::chrono::seconds idle_timeout = ipc::socket::kDefaultIdleTimeout;  // key idle_timeout_s
};

// `outputs.shm`: the POSIX shared-memory ring; the name as the socket's path.
struct ShmOutputConfig {
  std::string name = "/tofcompd";
  int slots = 64;
  unsigned mode = 0640;
};

struct OutputsConfig {
  SocketOutputConfig socket;
  ShmOutputConfig shm;
};

// `recording`: raw ranges, case readings and power to the interchange CSV
// (shared/docs/data-format.md), a new file when either rotation limit is reached.
struct RecordingConfig {
  bool enabled = false;
  // The system's; the reader puts who runs's (ipc/default_places.hpp).
  std::filesystem::path directory = "/var/lib/tofcompd/recordings";
  std::optional<long> max_rows;
  std::optional<long> max_minutes = 60;
  bool operator==(const RecordingConfig&) const = default;
};

enum class RecalibrationSource { None, Recording, PowerCycleRun };
enum class RecalibrationTrigger { OnRequest, AtStartIfMissing };

// `recalibration.power_cycle_run`: the calibration run of §8.1. The daemon switches the
// scanner's power on and off `cycles` times (on for on_s, off for off_s) with a target at a known
// distance before it, records what it measures, then trains on the recording.
struct PowerCycleRunConfig {
  int cycles = 3;
  double on_s = 3600.0;
  double off_s = 560.0;
  double true_range_mm = 0.0;       // the target's distance; required
  BeamRange beams;                  // the beams that face the target; training uses the middle one
  std::filesystem::path recording;  // the run's recording (measured-data CSV); required
  // The beam trained on: the middle of `beams`.
  int training_beam() const { return (beams.first + beams.last) / 2; }
};

// `recalibration.limits`: what one training may take (docs/daemon.md, "Recalibration").
inline constexpr std::chrono::seconds kDefaultTrainingTime{1800};
inline constexpr std::chrono::seconds kLargestTrainingTime{86400};
inline constexpr std::uint64_t kDefaultTrainingMemoryMib = 2048;
inline constexpr std::uint64_t kSmallestTrainingMemoryMib = 256;
inline constexpr std::uint64_t kLargestTrainingMemoryMib = 1u << 16;
inline constexpr std::uint64_t kDefaultRecordingMib = 256;
inline constexpr std::uint64_t kLargestRecordingMib = 4096;
struct RecalibrationLimits {
  std::chrono::seconds time = kDefaultTrainingTime;      // key time_s: then the training stops
  std::uint64_t memory_mib = kDefaultTrainingMemoryMib;  // the training process's address space
  std::uint64_t recording_mib = kDefaultRecordingMib;    // the largest recording trained on
  bool operator==(const RecalibrationLimits&) const = default;
};

// `recalibration`: where a new calibration comes from and when it is made.
struct RecalibrationConfig {
  RecalibrationSource source = RecalibrationSource::None;
  RecalibrationTrigger trigger = RecalibrationTrigger::OnRequest;
  std::filesystem::path datasheet;  // Algorithm 1's datasheet values; empty: the built-in LMS 200's
  std::filesystem::path output;     // where the calibration is written; default calibration.file
  std::filesystem::path data;       // source recording: the interchange CSV to train on
  // source recording: the one directory a client's recalibrate may name a recording in (key
  // recording.directory); by default the directory of `data`.
  std::filesystem::path recordings_directory;
  RecalibrationLimits limits;
  // Closing the loop (docs/closing-the-loop.md): the model search runs on the part trained on and
  // the calibration carries the terms it keeps. Key model_search.
  bool model_search = true;
  PowerCycleRunConfig power_cycle_run;  // source power_cycle_run
};

// `log`
struct LogConfig {
  spdlog::level::level_enum level = spdlog::level::info;
  LogTarget target = LogTarget::Auto;
};

struct DaemonConfig {
  std::string source;  // where it was read from ("/etc/tofcompd/tofcompd.yaml"), for messages
  LinkConfig link;
  EmulatorConfig emulator;
  CaseSensorConfig case_sensor;
  PowerConfig power;
  CalibrationConfig calibration;
  CompensationConfig compensation;
  OutputsConfig outputs;
  RecordingConfig recording;
  RecalibrationConfig recalibration;
  LogConfig log;
};

// "none", "recording", "power_cycle_run"; "on_request", "at_start_if_missing".
std::string to_string(RecalibrationSource source);
std::string to_string(RecalibrationTrigger trigger);

// The rules that join keys of different sections (each key's own range is checked by the
// reader). Throws DaemonConfigError (settings/daemon_config_error.hpp) starting with
// config.source and naming every key involved, e.g. a simulated case sensor without the
// emulator, a beam outside the scan, a recalibration with nowhere to write.
void validate(const DaemonConfig& config);

// The keys (paths such as "link.baud", "outputs.shm.name") whose values differ between `old`
// and `next` and which a reload cannot apply to the running daemon: the process must restart
// for them. Changes under calibration, compensation, recording, recalibration and log.level
// apply live and are never listed. Empty when a reload can apply everything.
std::vector<std::string> keys_needing_restart(const DaemonConfig& old, const DaemonConfig& next);

}  // namespace tofcomp::settings
