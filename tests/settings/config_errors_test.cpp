// Each kind of error in one key names the file and the key path and says what was expected:
// unknown keys at several depths, wrong types, values out of range, bad choices, missing
// required keys, keys given twice, and YAML syntax errors with their line.
#include "config_test_support.hpp"

namespace tofcomp::settings {
namespace {

using testing::error_of;
using testing::kMinimal;
using testing::parse;

// The message starts with the file and holds `expected`.
void expect_error(const std::string& text, const std::string& expected) {
  const std::string message = error_of(text);
  EXPECT_EQ(message.rfind("test.yaml", 0), 0u) << message;
  EXPECT_NE(message.find(expected), std::string::npos)
      << "expected \"" << expected << "\" in: " << message;
}

TEST(ConfigErrors, MinimalConfigurationParses) {
  const DaemonConfig c = parse(kMinimal);
  EXPECT_EQ(c.link.device, "/dev/ttyS0");
  const auto* hwmon = std::get_if<hal::HwmonSensorConfig>(&c.case_sensor.sensor.backend);
  ASSERT_NE(hwmon, nullptr);
  EXPECT_EQ(hwmon->name, "lm75");
  EXPECT_EQ(hwmon->channel, 1);
  EXPECT_FALSE(c.emulator.enabled);
  EXPECT_TRUE(c.calibration.file.empty());
}

TEST(ConfigErrors, RecalibrationWithoutADatasheetTakesTheBuiltInOne) {
  const DaemonConfig c =
      parse(kMinimal + "recalibration: {source: recording, output: c.yaml, recording: {data: "
                       "r.csv}}\n");
  EXPECT_TRUE(c.recalibration.datasheet.empty());  // io::datasheet_or_bundled: the LMS 200's
}

TEST(ConfigErrors, UnknownKeysAtEveryDepth) {
  expect_error(kMinimal + "links: {}\n", "test.yaml: links is not a known key; allowed here:");
  expect_error(
      "link: {device: /dev/ttyS0, bauds: 9600}\n"
      "case_sensor: {backend: hwmon, hwmon: {name: lm75}}\n",
      "test.yaml: link.bauds is not a known key");
  expect_error(
      "link: {device: /dev/ttyS0, variant: {field: 180}}\n"
      "case_sensor: {backend: hwmon, hwmon: {name: lm75}}\n",
      "test.yaml: link.variant.field is not a known key");
  expect_error(
      "link: {device: /dev/ttyS0}\n"
      "case_sensor: {backend: hwmon, hwmon: {name: lm75, chanel: 2}}\n",
      "test.yaml: case_sensor.hwmon.chanel is not a known key");
  expect_error(kMinimal + "emulator: {faults: {garbage: 0.1, dropped: 0.1}}\n",
               "test.yaml: emulator.faults.dropped is not a known key");
}

TEST(ConfigErrors, WrongTypes) {
  expect_error(kMinimal + "compensation: {window: abc}\n",
               "test.yaml: compensation.window must be a whole number, not 'abc'");
  expect_error(kMinimal + "compensation: {window: 200.5}\n",
               "compensation.window must be a whole number, not '200.5'");
  expect_error(kMinimal + "compensation: {window: 0100}\n",
               "compensation.window must be written without a leading 0 (YAML would read "
               "\"0100\" as octal)");
  expect_error(kMinimal + "compensation: {em: {method: fast}}\n", "compensation.em.method");
  expect_error(kMinimal + "recording: {enabled: maybe}\n",
               "test.yaml: recording.enabled must be true or false");
  expect_error(kMinimal + "compensation: {change_detector: {drift: [1, 2]}}\n",
               "compensation.change_detector.drift must be a finite number");
  expect_error(kMinimal + "outputs: {socket: 5}\n",
               "test.yaml: outputs.socket must be a mapping of keys to values");
  expect_error("- link\n", "test.yaml: the document must be a mapping of keys to values");
  expect_error(kMinimal + "compensation: {beams: [0, 360]}\n", "compensation.beams");
}

TEST(ConfigErrors, ValuesOutOfRange) {
  expect_error(kMinimal + "compensation: {window: 1}\n",
               "test.yaml: compensation.window must be between 2 and 100000, not 1");
  expect_error(kMinimal + "outputs: {shm: {slots: 1}}\n",
               "test.yaml: outputs.shm.slots must be between 2 and 1048576, not 1");
  expect_error(kMinimal + "emulator: {faults: {garbage: 1.5}}\n",
               "test.yaml: emulator.faults.garbage must be between 0 and 1, not 1.5");
  expect_error(kMinimal + "emulator: {faults: {stall_s: 0}}\n",
               "emulator.faults.stall_s must be greater than 0 and at most 3600, not 0");
  expect_error(kMinimal + "calibration: {file: c.yaml, noise: {sensor_noise_k2: 0}}\n",
               "calibration.noise.sensor_noise_k2 must be greater than 0, not 0");
  expect_error(kMinimal + "compensation: {change_detector: {threshold: .nan}}\n",
               "compensation.change_detector.threshold must be a finite number");
  expect_error(kMinimal + "compensation: {em: {refreshes: -1}}\n",
               "compensation.em.refreshes must be between 0 and 100000, not -1");
  expect_error(
      "link: {device: /dev/ttyS0}\n"
      "case_sensor: {backend: i2c, i2c: {address: 0x80}}\n",
      "case_sensor.i2c.address must be a 7-bit address between 0x08 and 0x77, not 0x80");
  expect_error(kMinimal + "outputs: {socket: {path: /" + std::string(120, 's') + "}}\n",
               "outputs.socket.path is 121 bytes long once resolved; a Unix socket path has at "
               "most 107");
}

TEST(ConfigErrors, BadChoices) {
  expect_error(
      "link: {device: /dev/ttyS0, units: inch}\n"
      "case_sensor: {backend: hwmon, hwmon: {name: lm75}}\n",
      "test.yaml: link.units must be one of mm, cm, not \"inch\"");
  expect_error(
      "link: {device: /dev/ttyS0, baud: 115200}\n"
      "case_sensor: {backend: hwmon, hwmon: {name: lm75}}\n",
      "test.yaml: link.baud must be one of 9600, 19200, 38400, 500000, not 115200");
  expect_error(
      "link: {device: /dev/ttyS0, variant: {resolution_deg: 0.3}}\n"
      "case_sensor: {backend: hwmon, hwmon: {name: lm75}}\n",
      "link.variant.resolution_deg must be one of 1, 0.5, 0.25, not 0.3");
  expect_error("link: {device: /dev/ttyS0}\ncase_sensor: {backend: thermocouple}\n",
               "case_sensor.backend must be one of hwmon, i2c, w1, simulated, not "
               "\"thermocouple\"");
  expect_error(kMinimal + "log: {level: loud}\n", "test.yaml: log.level is not valid:");
  expect_error(kMinimal + "log: {target: syslog}\n", "test.yaml: log.target is not valid:");
  expect_error(kMinimal + "outputs: {socket: {mode: rw}}\n",
               "test.yaml: outputs.socket.mode must be an octal mode like \"0660\", not \"rw\"");
  expect_error(kMinimal + "outputs: {shm: {mode: \"0860\"}}\n",
               "outputs.shm.mode must be an octal mode like \"0660\", not \"0860\"");
  expect_error(kMinimal + "outputs: {shm: {name: tofcompd}}\n",
               "outputs.shm.name must be a shared-memory name like \"/tofcompd\"");
  expect_error(kMinimal + "compensation: {em: {m_step: fast}}\n",
               "compensation.em.m_step must be one of exact, paper, not \"fast\"");
  expect_error(
      kMinimal + "recalibration: {source: magic}\n",
      "recalibration.source must be one of none, recording, power_cycle_run, not \"magic\"");
  expect_error("link: {device: /dev/ttyS0}\ncase_sensor: {backend: w1, w1: {device_id: 10-abc}}\n",
               "case_sensor.w1.device_id must be a DS18B20 id like \"28-0000075565b2\"");
}

TEST(ConfigErrors, OctalModesAndHexAddressesAreRead) {
  const DaemonConfig c = parse(
      "link: {device: /dev/ttyS0}\n"
      "case_sensor: {backend: i2c, i2c: {address: 0x49, chip: tmp117}}\n"
      "outputs: {socket: {mode: 0600}, shm: {mode: \"644\"}}\n");
  EXPECT_EQ(c.outputs.socket.mode, 0600u);  // unquoted: still read as the octal digits written
  EXPECT_EQ(c.outputs.shm.mode, 0644u);
  const auto& i2c = std::get<hal::I2cSensorConfig>(c.case_sensor.sensor.backend);
  EXPECT_EQ(i2c.address, 0x49);
  EXPECT_EQ(i2c.chip, hal::TmpChip::Tmp117);
  EXPECT_EQ(i2c.device, "/dev/i2c-1");
}

TEST(ConfigErrors, MissingRequiredKeys) {
  expect_error("link: {device: /dev/ttyS0}\n", "test.yaml: case_sensor is missing");
  expect_error("link: {device: /dev/ttyS0}\ncase_sensor:\n", "test.yaml: case_sensor is missing");
  expect_error("link: {device: /dev/ttyS0}\ncase_sensor: {hwmon: {name: lm75}}\n",
               "test.yaml: case_sensor.backend is missing");
  expect_error("link: {device: /dev/ttyS0}\ncase_sensor: {backend: hwmon}\n",
               "test.yaml: case_sensor.hwmon is missing: backend hwmon needs its directory or "
               "name");
  expect_error("link: {device: /dev/ttyS0}\ncase_sensor: {backend: w1, w1: {}}\n",
               "test.yaml: case_sensor.w1.device_id is missing");
  expect_error("case_sensor: {backend: hwmon, hwmon: {name: lm75}}\n",
               "test.yaml: link.device is missing: give the serial port, or set "
               "emulator.enabled: true");
  expect_error(kMinimal + "power: {switch: {chip: gpiochip0}}\n",
               "test.yaml: power.switch.line is missing");
  expect_error(kMinimal + "calibration: {ambient_c: 20}\n",
               "test.yaml: calibration.file is missing");
  expect_error("case_sensor: {backend: simulated}\nemulator: {enabled: true}\n",
               "test.yaml: emulator.scenario is missing");
  expect_error(kMinimal +
                   "recalibration: {source: recording, datasheet: d.yaml, output: c.yaml,"
                   " recording: {}}\n",
               "test.yaml: recalibration.recording.data is missing");
  expect_error(kMinimal + "recording: {rotation: {}}\n",
               "test.yaml: recording.rotation must give max_rows, max_minutes or both");
}

TEST(ConfigErrors, SectionsOfAnotherBackendOrSource) {
  expect_error(
      "link: {device: /dev/ttyS0}\n"
      "case_sensor: {backend: hwmon, hwmon: {name: lm75}, i2c: {address: 0x48}}\n",
      "test.yaml: case_sensor.i2c applies to backend i2c only; backend is hwmon");
  expect_error(kMinimal + "recalibration: {source: none, recording: {data: r.csv}}\n",
               "test.yaml: recalibration.recording applies to source recording only; source is "
               "none");
  expect_error(
      "link: {device: /dev/ttyS0}\n"
      "case_sensor: {backend: hwmon, hwmon: {name: lm75, directory: /sys/x}}\n",
      "test.yaml: case_sensor.hwmon must give exactly one of directory and name");
}

// recalibration.power_cycle_run: each bad key is named with what it must be.
TEST(ConfigErrors, PowerCycleRunKeysAreCheckedAndNamed) {
  const std::string head =
      kMinimal +
      "power: {switch: {chip: gpiochip0, line: 17}}\n"
      "recalibration: {source: power_cycle_run, datasheet: d.yaml, output: c.yaml,\n"
      "  power_cycle_run: {";
  const std::string good = "true_range_mm: 3000, beams: {first: 180}, recording: run.csv";
  expect_error(head + good + ", cycles: 0}}\n",
               "test.yaml: recalibration.power_cycle_run.cycles must be between 1 and 1000, not 0");
  expect_error(head + good + ", on_s: 0}}\n",
               "test.yaml: recalibration.power_cycle_run.on_s must be greater than 0 and at most "
               "86400, not 0");
  expect_error(head + good + ", off_s: -5}}\n",
               "test.yaml: recalibration.power_cycle_run.off_s must be greater than 0 and at most "
               "86400, not -5");
  expect_error(head + "beams: {first: 180}, recording: run.csv}}\n",
               "test.yaml: recalibration.power_cycle_run.true_range_mm is missing");
  expect_error(head + "true_range_mm: 3000, recording: run.csv}}\n",
               "test.yaml: recalibration.power_cycle_run.beams is missing");
  expect_error(head + "true_range_mm: 3000, beams: {first: 180}}}\n",
               "test.yaml: recalibration.power_cycle_run.recording is missing");
  expect_error(head + "true_range_mm: 3000, beams: {first: 180, last: 170}, recording: r.csv}}\n",
               "recalibration.power_cycle_run.beams.last must be at least "
               "recalibration.power_cycle_run.beams.first (180), not 170");
  expect_error(head + good + ", beam: 180}}\n", "recalibration.power_cycle_run.beam");
  expect_error(kMinimal + "recalibration: {source: recording, power_cycle_run: {cycles: 2}}\n",
               "test.yaml: recalibration.power_cycle_run applies to source power_cycle_run "
               "only; source is recording");
  const DaemonConfig c = parse(head + good + ", cycles: 2, on_s: 1.5, off_s: 0.5}}\n");
  EXPECT_EQ(c.recalibration.power_cycle_run.cycles, 2);
  EXPECT_EQ(c.recalibration.power_cycle_run.on_s, 1.5);
  EXPECT_EQ(c.recalibration.power_cycle_run.off_s, 0.5);
  EXPECT_EQ(c.recalibration.power_cycle_run.true_range_mm, 3000.0);
  EXPECT_EQ(c.recalibration.power_cycle_run.beams, (BeamRange{180, 180}));
}

TEST(ConfigErrors, KeyGivenTwiceNamesItsLine) {
  const std::string message = error_of(
      "link:\n"
      "  device: /dev/ttyS0\n"
      "  baud: 9600\n"
      "  baud: 38400\n"
      "case_sensor: {backend: hwmon, hwmon: {name: lm75}}\n");
  EXPECT_EQ(message, "test.yaml:4:3: link.baud is given twice");
}

TEST(ConfigErrors, SyntaxErrorNamesItsLine) {
  const std::string message = error_of(
      "link:\n"
      "  device: /dev/ttyS0\n"
      "  baud: [9600\n"
      "case_sensor: {backend: hwmon, hwmon: {name: lm75}}\n");
  // The unclosed flow sequence of line 3 runs into line 4, where yaml-cpp gives up.
  EXPECT_EQ(message.rfind("test.yaml:4:", 0), 0u) << message;
  EXPECT_NE(message.find("YAML syntax error"), std::string::npos) << message;

  const std::string tab = error_of("link:\n  device: /dev/ttyS0\n  baud: a: b\n");
  EXPECT_EQ(tab.rfind("test.yaml:3:", 0), 0u) << tab;
}

TEST(ConfigErrors, OtherShapesYamlAllows) {
  expect_error(kMinimal + "? [a, b]\n: 1\n", "has a key that is not plain text");
  expect_error(kMinimal + "---\nlog: {level: info}\n",
               "test.yaml:3:1: YAML syntax error: text after the end of the document");
  // yaml-cpp 0.7's LoadAll reports documents without end for this one (found by the fuzzer).
  expect_error(",", "test.yaml:1:1: YAML syntax error");
  expect_error("&a [*a]\n", "test.yaml");
  expect_error("", "test.yaml: case_sensor is missing");
  // Ten aliases of ten aliases of ...: 10^9 values if walked naively.
  std::string laughs = "l0: &l0 [x, x, x, x, x, x, x, x, x, x]\n";
  for (int i = 1; i <= 9; ++i) {
    const std::string prev = "*l" + std::to_string(i - 1);
    laughs += "l" + std::to_string(i) + ": &l" + std::to_string(i) + " [" + prev;
    for (int k = 1; k < 10; ++k) laughs += ", " + prev;
    laughs += "]\n";
  }
  expect_error(laughs, "test.yaml: holds more than 100000 values");
}

TEST(ConfigErrors, MissingFileNamesIt) {
  try {
    load_daemon_config("/nonexistent/tofcompd.yaml");
    FAIL() << "a missing file was read";
  } catch (const DaemonConfigError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("/nonexistent/tofcompd.yaml: cannot be read", 0), 0u)
        << e.what();
  }
}

}  // namespace
}  // namespace tofcomp::settings
