// The rules joining keys (validate()): each broken rule is an error naming every key involved,
// and the configuration just inside each rule is accepted.
#include "config_test_support.hpp"

namespace tofcomp::settings {
namespace {

using testing::error_of;
using testing::kMinimal;
using testing::parse;

// The message starts with the file and names every key in `keys`.
void expect_rule(const std::string& text, std::initializer_list<std::string> keys) {
  const std::string message = error_of(text);
  EXPECT_EQ(message.rfind("test.yaml: ", 0), 0u) << message;
  for (const auto& key : keys) {
    EXPECT_NE(message.find(key), std::string::npos) << "expected " << key << " in: " << message;
  }
}

const std::string kEmulated =
    "emulator: {enabled: true, scenario: scenarios/default.yaml}\n"
    "case_sensor: {backend: simulated}\n";

TEST(CrossFieldRules, SimulatedSensorNeedsTheEmulator) {
  expect_rule("link: {device: /dev/ttyS0}\ncase_sensor: {backend: simulated}\n",
              {"case_sensor.backend", "emulator.enabled"});
  expect_rule(
      "link: {device: /dev/ttyS0}\ncase_sensor: {backend: simulated}\n"
      "emulator: {enabled: false, scenario: s.yaml}\n",
      {"case_sensor.backend", "emulator.enabled"});
  EXPECT_TRUE(parse(kEmulated).emulator.enabled);
}

TEST(CrossFieldRules, LinkDeviceIsTheEmulatorsWhileItRuns) {
  // Left out, the device is the emulator's link path.
  const DaemonConfig c = parse(
      "emulator: {enabled: true, scenario: s.yaml, link: /run/tofcompd/lms200}\n"
      "case_sensor: {backend: simulated}\n");
  EXPECT_EQ(c.link.device, "/run/tofcompd/lms200");
  // Naming the same path is fine; another is a contradiction.
  EXPECT_NO_THROW(
      parse("link: {device: /run/tofcompd/lms200}\n"
            "emulator: {enabled: true, scenario: s.yaml, link: /run/tofcompd/lms200}\n"
            "case_sensor: {backend: simulated}\n"));
  expect_rule("link: {device: /dev/ttyUSB0}\n" + kEmulated, {"link.device", "emulator.enabled"});
}

TEST(CrossFieldRules, Rs232UnitRefuses500k) {
  expect_rule(
      "link: {baud: 500000}\n"
      "emulator: {enabled: true, scenario: s.yaml, rs232: true}\n"
      "case_sensor: {backend: simulated}\n",
      {"link.baud", "emulator.rs232"});
  EXPECT_NO_THROW(
      parse("link: {baud: 38400}\n"
            "emulator: {enabled: true, scenario: s.yaml, rs232: true}\n"
            "case_sensor: {backend: simulated}\n"));
}

TEST(CrossFieldRules, VariantAndBackoff) {
  expect_rule(
      "link: {device: /dev/ttyS0, variant: {field_deg: 180, resolution_deg: 0.25}}\n"
      "case_sensor: {backend: hwmon, hwmon: {name: lm75}}\n",
      {"link.variant.resolution_deg", "link.variant.field_deg"});
  EXPECT_NO_THROW(
      parse("link: {device: /dev/ttyS0, variant: {field_deg: 100, resolution_deg: 0.25}}\n"
            "case_sensor: {backend: hwmon, hwmon: {name: lm75}}\n"));
  expect_rule(
      "link: {device: /dev/ttyS0, backoff: {initial_ms: 500, max_ms: 100}}\n"
      "case_sensor: {backend: hwmon, hwmon: {name: lm75}}\n",
      {"link.backoff.max_ms", "link.backoff.initial_ms"});
}

TEST(CrossFieldRules, FaultRatesAddUpToAtMostOne) {
  expect_rule(kMinimal + "emulator: {faults: {garbage: 0.6, stall: 0.5}}\n",
              {"emulator.faults", "1.1"});
  EXPECT_NO_THROW(parse(kMinimal + "emulator: {faults: {garbage: 0.5, stall: 0.5}}\n"));
}

TEST(CrossFieldRules, SensorStalenessAndLimits) {
  expect_rule(
      "link: {device: /dev/ttyS0}\n"
      "case_sensor: {backend: hwmon, hwmon: {name: lm75}, poll_interval_ms: 2000,"
      " stale_after_s: 2}\n",
      {"case_sensor.stale_after_s", "case_sensor.poll_interval_ms"});
  EXPECT_NO_THROW(
      parse("link: {device: /dev/ttyS0}\n"
            "case_sensor: {backend: hwmon, hwmon: {name: lm75}, poll_interval_ms: 2000,"
            " stale_after_s: 2.5}\n"));
  expect_rule(
      "link: {device: /dev/ttyS0}\n"
      "case_sensor: {backend: hwmon, hwmon: {name: lm75}, limits: {min_c: 50, max_c: 40}}\n",
      {"case_sensor.limits.min_c", "case_sensor.limits.max_c"});
}

TEST(CrossFieldRules, WindowAndBeamsFitTheScan) {
  expect_rule(kMinimal + "compensation: {window: 20, min_samples: 21}\n",
              {"compensation.min_samples", "compensation.window"});
  EXPECT_NO_THROW(parse(kMinimal + "compensation: {window: 20, min_samples: 20}\n"));
}

TEST(CrossFieldRules, RecalibrationNeedsSomewhereToWriteAndAPowerSwitch) {
  expect_rule(kMinimal +
                  "recalibration: {source: recording, datasheet: d.yaml,"
                  " recording: {data: r.csv}}\n",
              {"recalibration.output", "calibration.file"});
  expect_rule(kMinimal +
                  "recalibration: {source: recording, datasheet: d.yaml, output: r.csv,"
                  " recording: {data: r.csv}}\n",
              {"recalibration.output", "recalibration.recording.data"});
  const DaemonConfig c = parse(kMinimal +
                               "calibration: {file: c.yaml}\n"
                               "recalibration: {source: recording, datasheet: d.yaml,"
                               " recording: {data: r.csv}}\n");
  EXPECT_EQ(c.recalibration.output, "/etc/tofcompd/c.yaml");  // calibration.file
}

TEST(CrossFieldRules, PowerCycleRunNeedsASwitchAndBeamsInTheScan) {
  const std::string run =
      "calibration: {file: c.yaml}\n"
      "recalibration: {source: power_cycle_run, datasheet: d.yaml,\n"
      "  power_cycle_run: {true_range_mm: 3000, recording: run.csv, beams: ";
  // Nothing to switch: neither a GPIO line nor the emulated scanner.
  expect_rule(kMinimal + run + "{first: 180}}}\n", {"recalibration.source", "power.switch"});
  const std::string gpio = "power: {switch: {chip: gpiochip0, line: 17}}\n";
  expect_rule(kMinimal + gpio + run + "{first: 178, last: 361}}}\n",
              {"recalibration.power_cycle_run.beams.last", "link.variant"});
  expect_rule(
      kMinimal + gpio + run.substr(0, run.find("run.csv")) + "c.yaml, beams: {first: 1}}}\n",
      {"recalibration.power_cycle_run.recording", "recalibration.output"});
  // Just inside: the last beam of 180° at 0.5°; the emulated scanner's supply as the switch.
  const DaemonConfig c = parse(kMinimal + gpio + run + "{first: 178, last: 360}}}\n");
  EXPECT_EQ(c.recalibration.source, RecalibrationSource::PowerCycleRun);
  EXPECT_EQ(c.recalibration.power_cycle_run.beams, (BeamRange{178, 360}));
  EXPECT_EQ(c.recalibration.power_cycle_run.training_beam(), 269);
  EXPECT_EQ(c.recalibration.power_cycle_run.recording, "/etc/tofcompd/run.csv");
  EXPECT_EQ(c.recalibration.power_cycle_run.cycles, 3);  // the defaults
  EXPECT_EQ(c.recalibration.power_cycle_run.on_s, 3600.0);
  EXPECT_EQ(c.recalibration.power_cycle_run.off_s, 560.0);
  EXPECT_NO_THROW(parse(kEmulated + run + "{first: 180}}}\n"));
}

TEST(CrossFieldRules, PlayingARecordingTakesItsCaseReadings) {
  expect_rule(
      "emulator: {enabled: true, scenario: s.yaml, recording: r.csv}\n"
      "case_sensor: {backend: hwmon, hwmon: {name: lm75}}\n",
      {"emulator.recording", "case_sensor.backend"});
  EXPECT_NO_THROW(parse(kEmulated.substr(0, kEmulated.find('}')) + ", recording: r.csv" +
                        kEmulated.substr(kEmulated.find('}'))));
}

TEST(CrossFieldRules, AtStartIfMissingWritesTheCalibrationFile) {
  expect_rule(kMinimal + "recalibration: {trigger: at_start_if_missing}\n",
              {"recalibration.trigger", "recalibration.source"});
  expect_rule(kMinimal +
                  "calibration: {file: c.yaml}\n"
                  "recalibration: {source: recording, trigger: at_start_if_missing,"
                  " datasheet: d.yaml, output: other.yaml, recording: {data: r.csv}}\n",
              {"recalibration.trigger", "calibration.file", "recalibration.output"});
  EXPECT_NO_THROW(parse(kMinimal +
                        "calibration: {file: c.yaml}\n"
                        "recalibration: {source: recording, trigger: at_start_if_missing,"
                        " datasheet: d.yaml, recording: {data: r.csv}}\n"));
}

TEST(CrossFieldRules, ValidateChecksConfigurationsBuiltInCode) {
  DaemonConfig c = parse(kMinimal);
  c.source = "built in code";
  c.compensation.window.min_samples = c.compensation.window.window + 1;
  try {
    validate(c);
    FAIL() << "min_samples above the window was accepted";
  } catch (const DaemonConfigError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("built in code: compensation.min_samples", 0), 0u)
        << e.what();
  }
}

}  // namespace
}  // namespace tofcomp::settings
