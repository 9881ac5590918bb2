// tofcomp-ros2-bridge's configuration: one YAML file with one section, `ros2:`
// (docs/integration.md, "ROS 2"; config/tofcomp-ros2-bridge.yaml). Read strictly, as the
// project's other YAML: an unknown key, a value of the wrong type or out of its bounds is an error
// naming the file, the key path and the rule.
#pragma once

#include <cstdint>
#include <string>

namespace tofcomp::bridges::ros2 {

// DDS domain ids a ROS 2 node may use (ROS_DOMAIN_ID): 0..232, the last for which the RTPS
// port formula (7400 + 250 × domain + offsets) stays below 65536.
inline constexpr long kMaxDomainId = 232;
// The longest frame_id and topic name accepted; ROS 2 itself allows no topic name longer than
// 255 characters once its "rt" prefix is added.
inline constexpr std::size_t kMaxFrameIdLength = 255;
inline constexpr std::size_t kMaxTopicNameLength = 250;
// The diagnostics period's bounds, in seconds (diagnostic_updater publishes once a second).
inline constexpr double kMinDiagnosticsPeriodS = 0.1;
inline constexpr double kMaxDiagnosticsPeriodS = 60.0;
inline constexpr double kDefaultDiagnosticsPeriodS = 1.0;

struct BridgeConfig {
  bool enabled = false;  // nothing is published unless the file says `enabled: true`
  std::uint32_t domain_id = 0;
  std::string frame_id = "laser";
  std::string scan_topic = "scan";               // ROS name; on the wire "rt/scan"
  std::string diagnostics_topic = "diagnostics";  // on the wire "rt/diagnostics"
  std::string socket_path;  // tofcompd's socket: from `socket`, `instance`, or the default
  double diagnostics_period_s = kDefaultDiagnosticsPeriodS;
};

// Parses the text of a configuration file; `source` names it in errors. Throws
// io::YamlSchemaError (a core::Error) naming the source, the key path and the reason.
// `instance` is the command line's --instance NAME, "" when not given (a single daemon). With a
// NAME, as tofcomp-mqtt-bridge's: the socket is that instance's unless the file names one
// (`socket`), and a file whose `instance` names another is refused, so that a per-instance unit
// (tofcomp-ros2-bridge@NAME.service) never publishes another scanner's scans under its name. A
// NAME that is no instance name throws core::InvalidInput (ipc::check_instance_name; the command
// line refuses it first).
BridgeConfig parse_bridge_config(const std::string& text, const std::string& source,
                                 const std::string& instance = {});

// Reads and parses a file (io::load_yaml_file's checks: a regular file, at most 16 MiB).
BridgeConfig load_bridge_config(const std::string& file, const std::string& instance = {});

// What the bridge will do, for its start-up log line and --check-config: "DDS domain 0,
// publishing rt/scan and rt/diagnostics from /run/tofcompd/tofcompd.sock".
std::string describe_bridge(const BridgeConfig& config);

// What is wrong with a ROS 2 topic name as this bridge accepts it, or "" when nothing is: one or
// more tokens of letters, digits and underscores, not starting with a digit, joined by single
// slashes, optionally with a leading slash (no "~", no substitutions, no trailing slash).
std::string topic_name_problem(const std::string& name);

// The DDS topic a ROS 2 node publishes the topic `name` on: "rt" and the fully qualified name
// ("scan" and "/scan" both give "rt/scan"), as rmw_cyclonedds makes it.
std::string dds_topic_name(const std::string& name);

}  // namespace tofcomp::bridges::ros2
