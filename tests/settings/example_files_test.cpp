// The two example configurations load and hold the values written in them; the built-in default
// is config/tofcompd.yaml; the settings they give pass the configured modules' own checks.
#include <fstream>
#include <sstream>

#include "config_test_support.hpp"
#include "hal/sensors/plausibility.hpp"
#include "settings/daemon_config_adapters.hpp"
#include "settings/embedded_default_config.hpp"

namespace tofcomp::settings {
namespace {

using namespace std::chrono_literals;
using testing::kConfigDir;

TEST(ExampleFiles, DefaultHoldsTheValuesWrittenInIt) {
  const DaemonConfig c = load_daemon_config(kConfigDir / "tofcompd.yaml");
  EXPECT_EQ(c.source, (kConfigDir / "tofcompd.yaml").string());

  EXPECT_TRUE(c.link.device.empty());  // the emulator's pty: no link path in the default
  EXPECT_EQ(c.link.baud, 500000u);
  EXPECT_EQ(c.link.variant, (hal::lms2xx::Variant{180, 50}));
  EXPECT_EQ(c.link.units, hal::lms2xx::Units::Millimetre);
  EXPECT_EQ(c.link.measuring_mode, hal::lms2xx::MeasuringMode::Range8m);
  EXPECT_EQ(c.link.ack_timeout, 60ms);
  EXPECT_EQ(c.link.reply_timeout, 200ms);
  EXPECT_EQ(c.link.scan_timeout, 1000ms);
  EXPECT_EQ(c.link.attempts, 3);
  EXPECT_EQ(c.link.backoff_initial, 50ms);
  EXPECT_EQ(c.link.backoff_max, 2000ms);

  EXPECT_TRUE(c.emulator.enabled);
  EXPECT_EQ(c.emulator.scenario, kConfigDir / "scenarios" / "default.yaml");
  EXPECT_EQ(c.emulator.time_scale, 1.0);
  EXPECT_EQ(c.emulator.faults.total(), 0.0);
  EXPECT_EQ(c.emulator.faults.stall_s, 0.5);
  EXPECT_EQ(c.emulator.faults.max_garbage_bytes, 16);
  EXPECT_EQ(c.emulator.fault_seed, 1u);
  EXPECT_TRUE(c.emulator.link.empty());
  EXPECT_FALSE(c.emulator.rs232);

  const auto* simulated = std::get_if<hal::SimulatedSensorConfig>(&c.case_sensor.sensor.backend);
  ASSERT_NE(simulated, nullptr);
  EXPECT_EQ(simulated->description, "twin case sensor");
  EXPECT_EQ(c.case_sensor.poll_interval, 1000ms);
  EXPECT_EQ(c.case_sensor.sensor.limits.max_age.count(), 10.0);
  EXPECT_EQ(c.case_sensor.sensor.limits.min_c, -40.0);
  EXPECT_EQ(c.case_sensor.sensor.limits.max_c, 125.0);
  EXPECT_EQ(c.case_sensor.sensor.limits.max_rate_c_per_s, 5.0);
  EXPECT_EQ(c.case_sensor.sensor.limits.jump_allowance_c, 0.5);

  EXPECT_FALSE(c.power.power_switch);
  EXPECT_FALSE(c.power.sense);

  EXPECT_EQ(c.calibration.file, kConfigDir / "calibration.yaml");
  EXPECT_EQ(c.calibration.kalman_noise, ThermalNoiseOverrides{});
  EXPECT_FALSE(c.calibration.ambient_c);

  EXPECT_EQ(c.compensation.window.window, 200);
  EXPECT_EQ(c.compensation.window.min_samples, 10);
  EXPECT_EQ(c.compensation.window.change.drift, 1.0);
  EXPECT_EQ(c.compensation.window.change.threshold, 12.0);
  EXPECT_EQ(c.compensation.window.em.distance_tolerance, 1e-6);
  EXPECT_EQ(c.compensation.window.em.max_iterations, 50);
  EXPECT_EQ(c.compensation.window.em.m_step, core::MStep::Exact);
  EXPECT_EQ(c.compensation.window.method, core::WindowEm::Incremental);
  EXPECT_EQ(c.compensation.window.refreshes, 4);

  EXPECT_EQ(c.outputs.socket.path, "/run/tofcompd/tofcompd.sock");
  EXPECT_EQ(c.outputs.socket.mode, 0660u);
  EXPECT_EQ(c.outputs.socket.max_clients, 16);
  EXPECT_EQ(c.outputs.socket.max_request_bytes, 4096u);
  EXPECT_EQ(c.outputs.socket.max_queued_bytes_per_client, 1048576u);
  EXPECT_EQ(c.outputs.shm.name, "/tofcompd");
  EXPECT_EQ(c.outputs.shm.slots, 64);
  EXPECT_EQ(c.outputs.shm.mode, 0640u);

  EXPECT_FALSE(c.recording.enabled);
  EXPECT_EQ(c.recording.directory, "/var/lib/tofcompd/recordings");
  EXPECT_EQ(c.recording.max_minutes, 60);
  EXPECT_FALSE(c.recording.max_rows);

  EXPECT_EQ(c.recalibration.source, RecalibrationSource::None);
  EXPECT_EQ(c.recalibration.trigger, RecalibrationTrigger::OnRequest);
  EXPECT_EQ(c.recalibration.output, c.calibration.file);

  EXPECT_EQ(c.log.level, spdlog::level::info);
  EXPECT_EQ(c.log.target, LogTarget::Auto);
}

TEST(ExampleFiles, HardwareHoldsTheValuesWrittenInIt) {
  const DaemonConfig c = load_daemon_config(kConfigDir / "tofcompd-hardware.yaml");
  EXPECT_EQ(c.link.device, "/dev/ttyUSB0");
  EXPECT_EQ(c.link.baud, 38400u);
  EXPECT_EQ(c.link.variant, (hal::lms2xx::Variant{180, 50}));
  EXPECT_EQ(c.link.backoff_initial, 100ms);
  EXPECT_EQ(c.link.backoff_max, 5000ms);
  EXPECT_FALSE(c.emulator.enabled);

  const auto* w1 = std::get_if<hal::W1SensorConfig>(&c.case_sensor.sensor.backend);
  ASSERT_NE(w1, nullptr);
  EXPECT_EQ(w1->device_id, "28-0000075565b2");
  EXPECT_EQ(w1->root, "/sys/bus/w1/devices");
  EXPECT_EQ(c.case_sensor.sensor.limits.min_c, -10.0);
  EXPECT_EQ(c.case_sensor.sensor.limits.max_c, 70.0);
  EXPECT_EQ(c.case_sensor.sensor.limits.max_rate_c_per_s, 2.0);

  ASSERT_TRUE(c.power.power_switch);
  EXPECT_EQ(c.power.power_switch->chip, "gpiochip0");
  EXPECT_EQ(c.power.power_switch->line, "17");
  EXPECT_FALSE(c.power.power_switch->active_low);
  ASSERT_TRUE(c.power.sense);
  EXPECT_EQ(c.power.sense->line, "27");
  EXPECT_TRUE(c.power.sense->active_low);

  EXPECT_EQ(c.calibration.file, "/var/lib/tofcompd/calibration.yaml");
  EXPECT_EQ(c.compensation.window.window, 400);
  EXPECT_EQ(c.compensation.window.min_samples, 20);
  EXPECT_EQ(c.compensation.window.method, core::WindowEm::Incremental);
  EXPECT_EQ(c.outputs.shm.slots, 128);

  EXPECT_TRUE(c.recording.enabled);
  EXPECT_EQ(c.recording.max_rows, 1000000);
  EXPECT_EQ(c.recording.max_minutes, 60);

  EXPECT_EQ(c.recalibration.source, RecalibrationSource::Recording);
  EXPECT_TRUE(c.recalibration.datasheet.empty());  // the built-in LMS 200 datasheet
  EXPECT_EQ(c.recalibration.output, "/var/lib/tofcompd/calibration.yaml");
  EXPECT_EQ(c.recalibration.data, "/var/lib/tofcompd/bench.csv");

  EXPECT_EQ(c.log.target, LogTarget::Journal);
}

TEST(ExampleFiles, BuiltInDefaultIsTheDefaultFile) {
  std::ifstream in(kConfigDir / "tofcompd.yaml");
  std::ostringstream text;
  text << in.rdbuf();
  EXPECT_EQ(embedded_default_config_text(), text.str());
  // Its paths are taken from the data directory beside the binary (io/data_directory.hpp), not
  // from the source tree: PREFIX/share/tofcomp for PREFIX/bin.
  EXPECT_EQ(embedded_default_config_directory().filename(), "tofcomp");
  EXPECT_EQ(embedded_default_config_directory().parent_path().filename(), "share");

  const DaemonConfig built_in = embedded_default_config(kConfigDir);
  const DaemonConfig from_file = load_daemon_config(kConfigDir / "tofcompd.yaml");
  EXPECT_TRUE(keys_needing_restart(built_in, from_file).empty());
  EXPECT_EQ(built_in.emulator.scenario, from_file.emulator.scenario);
  EXPECT_EQ(built_in.calibration.file, from_file.calibration.file);
}

TEST(ExampleFiles, SettingsPassTheModulesOwnChecks) {
  for (const char* name : {"tofcompd.yaml", "tofcompd-hardware.yaml"}) {
    SCOPED_TRACE(name);
    const DaemonConfig c = load_daemon_config(kConfigDir / name);
    EXPECT_NO_THROW(driver_settings(c.link, "/dev/pts/9").validate());
    EXPECT_NO_THROW(c.emulator.faults.validate());
    EXPECT_NO_THROW(hal::check_plausibility_limits(c.case_sensor.sensor.limits));
    // Builds the backend inside its plausibility check; opens nothing yet.
    EXPECT_NO_THROW(hal::make_temperature_sensor(c.case_sensor.sensor, [] { return 25.0; }));
  }
}

TEST(ExampleFiles, DriverSettingsCarryTheLink) {
  const DaemonConfig c = load_daemon_config(kConfigDir / "tofcompd-hardware.yaml");
  const auto settings = driver_settings(c.link);
  EXPECT_EQ(settings.device, "/dev/ttyUSB0");
  EXPECT_EQ(settings.baud, 38400u);
  EXPECT_EQ(settings.backoff_max, 5000ms);
  // Without a device of its own the link takes the emulator's.
  EXPECT_EQ(driver_settings(LinkConfig{}, "/dev/pts/3").device, "/dev/pts/3");
}

TEST(ExampleFiles, EmulatorSettingsLoadTheScenario) {
  const DaemonConfig c = load_daemon_config(kConfigDir / "tofcompd.yaml");
  const auto settings = emulator_settings(c);
  EXPECT_EQ(settings.scenario.name, "default");
  EXPECT_EQ(settings.scenario.true_range_mm, 3000.0);  // written in config/scenarios/default.yaml
  EXPECT_TRUE(settings.identity.supports_500k);

  DaemonConfig missing = c;
  missing.emulator.scenario = kConfigDir / "scenarios" / "no-such-scenario.yaml";
  try {
    emulator_settings(missing);
    FAIL() << "a missing scenario was accepted";
  } catch (const DaemonConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("emulator.scenario"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("no-such-scenario.yaml"), std::string::npos) << e.what();
  }
}

TEST(ExampleFiles, NoiseOverridesReplaceOnlyWhatTheyGive) {
  ThermalNoiseOverrides overrides;
  overrides.junction_process_psd_k2_per_s = 2e-4;
  core::ThermalNoise from_file;
  from_file.case_process_psd_k2_per_s = 3e-6;
  from_file.junction_process_psd_k2_per_s = 1e-4;
  from_file.measurement_variance_k2 = 1e-3;
  const core::ThermalNoise applied = overrides.applied_to(from_file);
  EXPECT_EQ(applied.case_process_psd_k2_per_s, 3e-6);
  EXPECT_EQ(applied.junction_process_psd_k2_per_s, 2e-4);
  EXPECT_EQ(applied.measurement_variance_k2, 1e-3);
}

}  // namespace
}  // namespace tofcomp::settings
