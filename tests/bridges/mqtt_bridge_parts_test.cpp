// tofcomp-mqtt-bridge's parts without a broker: its configuration (defaults, what each error
// names), the command topic's decisions, and the range summary's moments against values worked
// out by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "bridges/mqtt/bridge_config.hpp"
#include "bridges/mqtt/range_summary.hpp"
#include "bridges/mqtt/remote_command.hpp"
#include "core/error.hpp"

namespace tofcomp::bridges::mqtt {
namespace {

BridgeConfig parse(const std::string& text, const std::string& instance = "") {
  return parse_bridge_config(text, "bridge.yaml", "/etc/tofcomp-mqtt-bridge", instance);
}

std::string error_of(const std::string& text, const std::string& instance = "") {
  try {
    parse(text, instance);
  } catch (const core::InvalidInput& e) {
    return e.what();
  }
  return "accepted";
}

TEST(MqttBridgeConfig, DefaultsFollowTheInstanceAndTls) {
  const BridgeConfig plain = parse("broker: {host: b}\nsite: plant-a\n", "left");
  EXPECT_EQ(plain.broker.port, 1883);
  EXPECT_EQ(plain.broker.client_id, "tofcomp-plant-a-left");
  EXPECT_EQ(plain.instance, "left");
  EXPECT_EQ(plain.tofcompd_socket, "/run/tofcompd/left/tofcompd.sock");
  EXPECT_FALSE(plain.commands.reload);
  EXPECT_FALSE(plain.commands.recalibrate);
  const BridgeConfig tls = parse("broker: {host: b, tls: {ca_file: ca.crt}}\nsite: s\n");
  EXPECT_EQ(tls.broker.port, 8883);
  ASSERT_TRUE(tls.broker.tls.has_value());
  EXPECT_EQ(tls.broker.tls->ca_file, "/etc/tofcomp-mqtt-bridge/ca.crt");
  EXPECT_TRUE(tls.broker.tls->verify_hostname);
  EXPECT_EQ(tls.tofcompd_socket, "/run/tofcompd/tofcompd.sock");
  EXPECT_EQ(tls.instance, "default");
}

TEST(MqttBridgeConfig, ErrorsNameTheKey) {
  EXPECT_NE(error_of("broker: {host: b}\n").find("bridge.yaml: site is missing"), std::string::npos);
  EXPECT_NE(error_of("broker: {host: b, port: 0}\nsite: s\n")
                .find("broker.port must be between 1 and 65535, not 0"),
            std::string::npos);
  EXPECT_NE(error_of("broker: {host: b}\nsite: s\npublish: {status: 5}\n").find("publish.status"),
            std::string::npos);
  EXPECT_NE(error_of("broker: {host: b}\nsite: 'a/b'\n").find("site is no topic name"),
            std::string::npos);
  EXPECT_NE(error_of("broker: {host: b, password_file: p}\nsite: s\n")
                .find("broker.password_file needs broker.username"),
            std::string::npos);
  EXPECT_NE(error_of("broker: {host: b, tls: {ca_file: c, cert_file: x}}\nsite: s\n")
                .find("broker.tls.key_file is missing"),
            std::string::npos);
  EXPECT_NE(error_of("broker: {host: b}\nsite: s\ninstance: right\n", "left")
                .find("instance is 'right', but --instance names 'left'"),
            std::string::npos);
  EXPECT_NE(error_of("broker: {host: b}\nsite: s\nreconnect: {initial_s: 9, max_s: 2}\n")
                .find("reconnect.max_s must be at least reconnect.initial_s"),
            std::string::npos);
}

CommandDecision decide(const std::string& payload, bool reload, bool recalibrate) {
  return decide_command(payload, CommandPermissions{reload, recalibrate}, "b.yaml");
}

TEST(MqttBridgeCommands, OnlyAllowedControlOpsPass) {
  const CommandDecision refused = decide(R"({"id":4,"op":"reload"})", false, true);
  EXPECT_FALSE(refused.request.has_value());
  EXPECT_EQ(refused.refusal,
            R"({"id":4,"ok":false,"error":{"code":"forbidden","message":"reload: not allowed by )"
            R"(this bridge: commands.reload is false in b.yaml"}})");
  const CommandDecision passed = decide(R"({"id":"x","op":"reload"})", true, false);
  ASSERT_TRUE(passed.request.has_value());
  EXPECT_EQ(passed.request->dump(), R"({"op":"reload"})");
  EXPECT_EQ(passed.id, nlohmann::json("x"));
  const CommandDecision with_args =
      decide(R"({"op":"recalibrate","args":{"recording":"bench.csv"}})", false, true);
  ASSERT_TRUE(with_args.request.has_value());
  EXPECT_EQ(with_args.request->dump(), R"({"args":{"recording":"bench.csv"},"op":"recalibrate"})");
  for (const char* read_op : {R"({"op":"status"})", R"({"op":"subscribe"})"}) {
    const CommandDecision d = decide(read_op, true, true);
    EXPECT_FALSE(d.request.has_value()) << read_op;
    EXPECT_NE(d.refusal.find("not a command of the bridge"), std::string::npos) << d.refusal;
  }
  EXPECT_NE(decide("{\"op\":\"reload\"", true, true).refusal.find("bad_request"), std::string::npos);
  EXPECT_NE(decide(std::string(kMaxCommandBytes + 1, ' '), true, true).refusal.find("too_long"),
            std::string::npos);
  EXPECT_NE(decide(R"({"op":"reload","op":"reload"})", true, true).refusal.find("given twice"),
            std::string::npos);
}

TEST(MqttBridgeCommands, ARelayedReplyCarriesTheCommandsId) {
  EXPECT_EQ(relay_reply(nlohmann::json(7), R"({"id":123,"ok":true,"message":"reloaded x"})"),
            R"({"id":7,"ok":true,"message":"reloaded x"})");
}

client::Scan scan_of(std::uint64_t sequence, std::initializer_list<double> ranges,
                     std::uint16_t flags_of_last = 0) {
  client::Scan scan;
  scan.info.sequence = sequence;
  scan.info.timestamp_ns = static_cast<std::int64_t>(1000 + sequence);
  std::uint32_t index = 10;
  for (const double range : ranges) {
    client::Beam beam{};
    beam.index = index++;
    beam.compensated_mm = range;
    scan.beams.push_back(beam);
  }
  scan.beams.back().flags = flags_of_last;
  return scan;
}

TEST(MqttBridgeRangeSummary, MomentsSharesAndStepAsWorkedOut) {
  RangeSummary summary(2);  // beams 10 and 12 of 10..12
  const double nan = std::nan("");
  summary.add(scan_of(1, {3000.0, 1.0, 2000.0}));
  summary.add(scan_of(2, {3002.0, 1.0, nan}, 1u << 6));  // temperature_extrapolated on beam 12
  summary.add(scan_of(3, {3004.0, 1.0, 2000.5}));
  summary.add(scan_of(4, {3006.0, 1.0, 2001.0}, 1u));  // no_echo on beam 12
  const nlohmann::ordered_json out = summary.take();
  EXPECT_EQ(out["scans"], 4);
  EXPECT_EQ(out["first_beam"], 10);
  EXPECT_EQ(out["from_ns"], 1001);
  EXPECT_EQ(out["to_ns"], 1004);
  ASSERT_EQ(out["mean_mm"].size(), 2u);
  // Beam 10: 3000, 3002, 3004, 3006: mean 3003, population std sqrt(5) = 2.236...
  EXPECT_DOUBLE_EQ(out["mean_mm"][0].get<double>(), 3003.0);
  EXPECT_NEAR(out["std_mm"][0].get<double>(), 2.24, 1e-9);
  EXPECT_DOUBLE_EQ(out["valid_share"][0].get<double>(), 1.0);
  // Beam 12: 2000, 2000.5, 2001 (one scan without): mean 2000.5, std sqrt(1/6) = 0.408...
  EXPECT_DOUBLE_EQ(out["mean_mm"][1].get<double>(), 2000.5);
  EXPECT_NEAR(out["std_mm"][1].get<double>(), 0.41, 1e-9);
  EXPECT_DOUBLE_EQ(out["valid_share"][1].get<double>(), 0.75);
  // 12 ranges, one of each flag.
  EXPECT_NEAR(out["flag_share"]["temperature_extrapolated"].get<double>(), 0.083, 1e-9);
  EXPECT_NEAR(out["flag_share"]["no_echo"].get<double>(), 0.083, 1e-9);
  EXPECT_EQ(out["flag_share"]["outlier"].get<double>(), 0.0);
  EXPECT_EQ(summary.scans(), 0u);  // the next period starts empty
}

}  // namespace
}  // namespace tofcomp::bridges::mqtt
