// keys_needing_restart: known answers for changes a reload applies live (none listed) and for
// changes that need the daemon restarted (each listed by its key path).
#include "config_test_support.hpp"

namespace tofcomp::settings {
namespace {

using testing::parse;
using Keys = std::vector<std::string>;

const std::string kBase =
    "link: {device: /dev/ttyUSB0, baud: 38400}\n"
    "case_sensor: {backend: hwmon, hwmon: {name: lm75, channel: 1}}\n"
    "calibration: {file: /var/lib/tofcompd/calibration.yaml}\n"
    "outputs: {shm: {name: /tofcompd}}\n";

Keys restart_keys(const std::string& old_text, const std::string& next_text) {
  return keys_needing_restart(parse(old_text), parse(next_text));
}

TEST(Reload, SameConfigurationNeedsNothing) {
  EXPECT_EQ(restart_keys(kBase, kBase), Keys{});
}

TEST(Reload, LiveChangesAreNotListed) {
  EXPECT_EQ(restart_keys(kBase, kBase + "compensation: {window: 400, min_samples: 5,"
                                        " em: {m_step: paper, method: exact}}\n"),
            Keys{});
  EXPECT_EQ(restart_keys(kBase,
                         "link: {device: /dev/ttyUSB0, baud: 38400}\n"
                         "case_sensor: {backend: hwmon, hwmon: {name: lm75, channel: 1}}\n"
                         "calibration: {file: /var/lib/tofcompd/other.yaml,"
                         " noise: {sensor_noise_k2: 0.001}, ambient_c: 20}\n"
                         "outputs: {shm: {name: /tofcompd}}\n"),
            Keys{});
  EXPECT_EQ(restart_keys(kBase, kBase + "recording: {enabled: true, rotation: {max_rows: 10}}\n"
                                        "log: {level: debug}\n"
                                        "recalibration: {source: recording, datasheet: d.yaml,"
                                        " recording: {data: r.csv}}\n"),
            Keys{});
}

TEST(Reload, LinkAndOutputsNeedARestart) {
  EXPECT_EQ(restart_keys(kBase,
                         "link: {device: /dev/ttyUSB1, baud: 500000}\n"
                         "case_sensor: {backend: hwmon, hwmon: {name: lm75, channel: 1}}\n"
                         "calibration: {file: /var/lib/tofcompd/calibration.yaml}\n"
                         "outputs: {shm: {name: /tofcompd2}, socket: {path: /tmp/t.sock}}\n"),
            (Keys{"link.device", "link.baud", "outputs.socket.path", "outputs.shm.name"}));
  EXPECT_EQ(restart_keys(kBase, kBase + "log: {target: stderr, level: error}\n"),
            Keys{"log.target"});
}

TEST(Reload, SensorChangesNameTheBackendOrItsKey) {
  EXPECT_EQ(restart_keys(kBase,
                         "link: {device: /dev/ttyUSB0, baud: 38400}\n"
                         "case_sensor: {backend: w1, w1: {device_id: 28-0000075565b2}}\n"
                         "calibration: {file: /var/lib/tofcompd/calibration.yaml}\n"
                         "outputs: {shm: {name: /tofcompd}}\n"),
            Keys{"case_sensor.backend"});
  EXPECT_EQ(restart_keys(kBase,
                         "link: {device: /dev/ttyUSB0, baud: 38400}\n"
                         "case_sensor: {backend: hwmon, hwmon: {name: lm75, channel: 2},"
                         " limits: {max_c: 80}}\n"
                         "calibration: {file: /var/lib/tofcompd/calibration.yaml}\n"
                         "outputs: {shm: {name: /tofcompd}}\n"),
            (Keys{"case_sensor.hwmon.channel", "case_sensor.limits.max_c"}));
}

TEST(Reload, PowerLinesAndEmulator) {
  EXPECT_EQ(restart_keys(kBase, kBase + "power: {sense: {chip: gpiochip0, line: 27}}\n"),
            Keys{"power.sense"});
  EXPECT_EQ(restart_keys(kBase + "power: {sense: {chip: gpiochip0, line: 27}}\n",
                         kBase + "power: {sense: {chip: gpiochip0, line: 27, active_low: true}}\n"),
            Keys{"power.sense"});
  EXPECT_EQ(restart_keys(kBase, kBase + "emulator: {faults: {garbage: 0.01}, fault_seed: 7}\n"),
            (Keys{"emulator.faults.garbage", "emulator.fault_seed"}));
}

}  // namespace
}  // namespace tofcomp::settings
