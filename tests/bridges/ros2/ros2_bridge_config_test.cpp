// tofcomp-ros2-bridge's configuration (bridges/ros2/bridge_config.hpp): the defaults, and each
// kind of bad file refused with the source, the key path and the rule named.
#include <gtest/gtest.h>

#include <string>

#include "bridges/ros2/bridge_config.hpp"
#include "core/error.hpp"
#include "io/yaml_fields.hpp"
#include "ipc/instance_name.hpp"

namespace tofcomp::bridges::ros2 {
namespace {

// The message of the error parsing `text` throws; fails the test when it parses.
std::string error_of(const std::string& text) {
  try {
    parse_bridge_config(text, "bridge.yaml");
  } catch (const io::YamlSchemaError& e) {
    return e.what();
  }
  ADD_FAILURE() << "parsed:\n" << text;
  return {};
}

void expect_error(const std::string& text, const std::string& expected) {
  const std::string message = error_of(text);
  EXPECT_NE(message.find(expected), std::string::npos) << message << "\nlacks: " << expected;
  EXPECT_EQ(message.rfind("bridge.yaml", 0), 0u) << message;
}

TEST(Ros2BridgeConfig, DefaultsAreTheRos2NamesOnTheDefaultSocket) {
  const BridgeConfig c = parse_bridge_config("ros2:\n  enabled: true\n", "bridge.yaml");
  EXPECT_TRUE(c.enabled);
  EXPECT_EQ(c.domain_id, 0u);
  EXPECT_EQ(c.frame_id, "laser");
  EXPECT_EQ(dds_topic_name(c.scan_topic), "rt/scan");
  EXPECT_EQ(dds_topic_name(c.diagnostics_topic), "rt/diagnostics");
  EXPECT_EQ(c.socket_path, "/run/tofcompd/tofcompd.sock");
  EXPECT_DOUBLE_EQ(c.diagnostics_period_s, 1.0);
}

TEST(Ros2BridgeConfig, EveryKeyIsRead) {
  const BridgeConfig c = parse_bridge_config(
      "ros2:\n  enabled: false\n  domain_id: 42\n  frame_id: lms200_front\n"
      "  scan_topic: /robot1/scan\n  diagnostics_topic: robot1/diagnostics\n"
      "  instance: front\n  diagnostics_period_s: 2.5\n",
      "bridge.yaml");
  EXPECT_FALSE(c.enabled);
  EXPECT_EQ(c.domain_id, 42u);
  EXPECT_EQ(c.frame_id, "lms200_front");
  EXPECT_EQ(dds_topic_name(c.scan_topic), "rt/robot1/scan");
  EXPECT_EQ(dds_topic_name(c.diagnostics_topic), "rt/robot1/diagnostics");
  EXPECT_EQ(c.socket_path, "/run/tofcompd/front/tofcompd.sock");
  EXPECT_DOUBLE_EQ(c.diagnostics_period_s, 2.5);
  EXPECT_EQ(parse_bridge_config("ros2:\n  enabled: true\n  socket: /tmp/x.sock\n", "b").socket_path,
            "/tmp/x.sock");
}

TEST(Ros2BridgeConfig, BadFilesAreRefusedNamingTheKeyAndTheRule) {
  expect_error("", "must be a mapping");
  expect_error("ros2:\n  enabled: true\nmqtt: {}\n", "mqtt");
  expect_error("ros2:\n  domain_id: 1\n", "ros2.enabled is missing");
  expect_error("ros2:\n  enabled: yes please\n", "ros2.enabled must be true or false");
  expect_error("ros2:\n  enabled: true\n  domian_id: 3\n", "domian_id");
  expect_error("ros2:\n  enabled: true\n  domain_id: 233\n", "ros2.domain_id must be 0 to 232, not 233");
  expect_error("ros2:\n  enabled: true\n  domain_id: -1\n", "ros2.domain_id must be 0 to 232");
  expect_error("ros2:\n  enabled: true\n  domain_id: 1.5\n", "ros2.domain_id must be a whole number");
  expect_error("ros2:\n  enabled: true\n  frame_id: \"\"\n", "ros2.frame_id must not be empty");
  expect_error("ros2:\n  enabled: true\n  frame_id: my laser\n", "ros2.frame_id must be printable");
  expect_error("ros2:\n  enabled: true\n  frame_id: " + std::string(256, 'f') + "\n",
               "ros2.frame_id must be at most 255 characters");
  expect_error("ros2:\n  enabled: true\n  scan_topic: 2scan\n",
               "ros2.scan_topic '2scan' has a token that does not start");
  expect_error("ros2:\n  enabled: true\n  scan_topic: a//b\n", "ros2.scan_topic 'a//b' must not have an empty token");
  expect_error("ros2:\n  enabled: true\n  scan_topic: scan/\n", "ros2.scan_topic 'scan/' must not end with '/'");
  expect_error("ros2:\n  enabled: true\n  scan_topic: ~/scan\n", "ros2.scan_topic '~/scan'");
  expect_error("ros2:\n  enabled: true\n  scan_topic: sc-an\n", "may hold letters, digits, '_' and '/' only");
  expect_error("ros2:\n  enabled: true\n  diagnostics_topic: /scan\n",
               "ros2.diagnostics_topic must differ from scan_topic");
  expect_error("ros2:\n  enabled: true\n  socket: relative.sock\n", "ros2.socket must be an absolute path");
  expect_error("ros2:\n  enabled: true\n  socket: /a.sock\n  instance: front\n",
               "give either socket or instance, not both");
  expect_error("ros2:\n  enabled: true\n  instance: ../etc\n", "ros2.instance");
  expect_error("ros2:\n  enabled: true\n  diagnostics_period_s: 0.01\n",
               "ros2.diagnostics_period_s must be 0.1 to 60 s, not 0.01");
  expect_error("ros2:\n  enabled: true\n  diagnostics_period_s: .nan\n", "ros2.diagnostics_period_s");
  expect_error("ros2:\n  enabled: true\n  enabled: false\n", "enabled");  // a key twice
  expect_error("ros2: [1, 2]\n", "ros2");
}

// --instance NAME (tofcomp-ros2-bridge@NAME.service): the instance's socket unless the file names
// one; the file may name the same instance, and naming another is refused with the file and key.
TEST(Ros2BridgeConfig, TheCommandLinesInstanceGivesTheSocketAndRefusesAnother) {
  const std::string enabled = "ros2:\n  enabled: true\n";
  EXPECT_EQ(parse_bridge_config(enabled, "front.yaml", "front").socket_path,
            "/run/tofcompd/front/tofcompd.sock");
  EXPECT_EQ(parse_bridge_config(enabled + "  instance: front\n", "front.yaml", "front").socket_path,
            "/run/tofcompd/front/tofcompd.sock");
  EXPECT_EQ(
      parse_bridge_config(enabled + "  socket: /tmp/f.sock\n", "front.yaml", "front").socket_path,
      "/tmp/f.sock");
  // Without --instance, as before: the single daemon's socket.
  EXPECT_EQ(parse_bridge_config(enabled, "bridge.yaml").socket_path, "/run/tofcompd/tofcompd.sock");

  try {
    parse_bridge_config(enabled + "  instance: back\n", "/etc/tofcompd/ros2-bridge/front.yaml",
                        "front");
    ADD_FAILURE() << "a file naming instance back was accepted for --instance front";
  } catch (const io::YamlSchemaError& e) {
    EXPECT_STREQ(e.what(),
                 "/etc/tofcompd/ros2-bridge/front.yaml: ros2.instance is 'back', but --instance "
                 "names 'front'");
  }
  // The other rules still hold with --instance.
  EXPECT_THROW(parse_bridge_config(enabled + "  socket: rel.sock\n", "front.yaml", "front"),
               io::YamlSchemaError);
  EXPECT_THROW(parse_bridge_config(enabled + "  socket: /a.sock\n  instance: front\n", "front.yaml",
                                   "front"),
               io::YamlSchemaError);
}

// A bad --instance is refused by the daemon's rule (ipc::instance_name_problem) as the command
// line's error, not blamed on the file.
TEST(Ros2BridgeConfig, ABadCommandLineInstanceIsRefusedBeforeTheFile) {
  // A path, a leading '-', one byte over the longest name ("" is no --instance at all).
  for (const std::string& bad : {std::string("../etc"), std::string("-front"),
                                std::string(ipc::kMaxInstanceNameBytes + 1, 'a')}) {
    try {
      parse_bridge_config("ros2:\n  enabled: true\n", "bridge.yaml", bad);
      ADD_FAILURE() << "accepted --instance " << bad;
    } catch (const io::YamlSchemaError& e) {
      ADD_FAILURE() << "blamed the file: " << e.what();
    } catch (const core::Error& e) {
      EXPECT_NE(std::string(e.what()).find("'" + bad + "'"), std::string::npos) << e.what();
    }
  }
}

TEST(Ros2BridgeConfig, AFileIsReadWithItsNameInErrors) {
  EXPECT_THROW(load_bridge_config("/nonexistent/bridge.yaml"), io::YamlSchemaError);
  try {
    load_bridge_config("/nonexistent/bridge.yaml");
  } catch (const io::YamlSchemaError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/bridge.yaml"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tofcomp::bridges::ros2
