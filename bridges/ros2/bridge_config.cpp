#include "bridges/ros2/bridge_config.hpp"

#include <cctype>
#include <sstream>

#include "io/yaml_fields.hpp"
#include "ipc/instance_name.hpp"
#include "tofcomp/tofcomp_client.h"

namespace tofcomp::bridges::ros2 {

namespace {

bool token_start(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool token_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

std::string frame_id_problem(const std::string& frame_id) {
  if (frame_id.empty()) return "must not be empty";
  if (frame_id.size() > kMaxFrameIdLength) {
    return "must be at most " + std::to_string(kMaxFrameIdLength) + " characters";
  }
  for (const char c : frame_id) {
    if (!std::isgraph(static_cast<unsigned char>(c))) {
      return "must be printable ASCII without spaces";
    }
  }
  return {};
}

std::string checked_topic(const io::YamlMap& section, std::string_view key, std::string fallback) {
  std::string name = section.text_or(key, std::move(fallback));
  if (const std::string problem = topic_name_problem(name); !problem.empty()) {
    section.fail(key, "'" + name + "' " + problem);
  }
  return name;
}

// The socket named by `socket`, by `instance` (its socket), by the command line's --instance
// (`command_line_instance`, "" when not given), or tofcompd's default one. A file's `instance`
// other than the command line's is refused: it is the wrong file for this unit.
std::string socket_of(const io::YamlMap& section, const std::string& command_line_instance) {
  if (section.has("socket") && section.has("instance")) {
    section.fail("instance", "give either socket or instance, not both");
  }
  if (section.has("instance")) {
    const std::string instance = section.text("instance");
    if (const std::string problem = ipc::instance_name_problem(instance); !problem.empty()) {
      section.fail("instance", problem);
    }
    if (!command_line_instance.empty() && instance != command_line_instance) {
      section.fail("instance",
                   "is '" + instance + "', but --instance names '" + command_line_instance + "'");
    }
    return ipc::instance_socket_path(instance);
  }
  if (!section.has("socket")) {
    return command_line_instance.empty() ? std::string(TOFCOMP_DEFAULT_SOCKET_PATH)
                                         : ipc::instance_socket_path(command_line_instance);
  }
  std::string path = section.text("socket");
  if (path.empty() || path.front() != '/') section.fail("socket", "must be an absolute path");
  return path;
}

}  // namespace

std::string topic_name_problem(const std::string& name) {
  if (name.empty()) return "must not be empty";
  if (name.size() > kMaxTopicNameLength) {
    return "must be at most " + std::to_string(kMaxTopicNameLength) + " characters";
  }
  const std::size_t start = name.front() == '/' ? 1 : 0;
  bool at_token_start = true;
  for (std::size_t i = start; i < name.size(); ++i) {
    const char c = name[i];
    if (c == '/') {
      if (at_token_start) return "must not have an empty token (\"//\" or a leading \"/\" alone)";
      at_token_start = true;
    } else if (at_token_start) {
      if (!token_start(c)) return "has a token that does not start with a letter or '_'";
      at_token_start = false;
    } else if (!token_char(c)) {
      return "may hold letters, digits, '_' and '/' only";
    }
  }
  if (at_token_start) return "must not end with '/'";
  return {};
}

std::string dds_topic_name(const std::string& name) {
  return name.front() == '/' ? "rt" + name : "rt/" + name;
}

namespace {

BridgeConfig bridge_config_of(const YAML::Node& root, const std::string& instance) {
  const io::YamlMap top(root, "", {"ros2"});
  const io::YamlMap section(top.node("ros2"), top.child_path("ros2"),
                            {"enabled", "domain_id", "frame_id", "scan_topic", "diagnostics_topic",
                             "socket", "instance", "diagnostics_period_s"});
  BridgeConfig config;
  config.enabled = section.boolean("enabled");
  const long domain = section.integer_or("domain_id", 0);
  if (domain < 0 || domain > kMaxDomainId) {
    section.fail("domain_id", "must be 0 to " + std::to_string(kMaxDomainId) + ", not " +
                                  std::to_string(domain));
  }
  config.domain_id = static_cast<std::uint32_t>(domain);
  config.frame_id = section.text_or("frame_id", config.frame_id);
  if (const std::string problem = frame_id_problem(config.frame_id); !problem.empty()) {
    section.fail("frame_id", problem);
  }
  config.scan_topic = checked_topic(section, "scan_topic", config.scan_topic);
  config.diagnostics_topic = checked_topic(section, "diagnostics_topic", config.diagnostics_topic);
  if (dds_topic_name(config.scan_topic) == dds_topic_name(config.diagnostics_topic)) {
    section.fail("diagnostics_topic", "must differ from scan_topic");
  }
  config.socket_path = socket_of(section, instance);
  config.diagnostics_period_s = section.number_or("diagnostics_period_s", config.diagnostics_period_s);
  if (!(config.diagnostics_period_s >= kMinDiagnosticsPeriodS &&
        config.diagnostics_period_s <= kMaxDiagnosticsPeriodS)) {
    std::ostringstream why;
    why << "must be " << kMinDiagnosticsPeriodS << " to " << kMaxDiagnosticsPeriodS << " s, not "
        << config.diagnostics_period_s;
    section.fail("diagnostics_period_s", why.str());
  }
  return config;
}

// The document's settings, each error prefixed with the source ("bridge.yaml: ros2.domain_id
// must be ..."); load_yaml_* name the source and the line themselves.
BridgeConfig bridge_config_in(const YAML::Node& document, const std::string& source,
                              const std::string& instance) {
  try {
    return bridge_config_of(document, instance);
  } catch (const YAML::Exception& e) {
    throw io::YamlSchemaError(io::yaml_position(source, e.mark) + ": " + e.msg);
  } catch (const core::Error& e) {
    throw io::YamlSchemaError(source + ": " + e.what());
  }
}

// A bad --instance is the command line's fault, not the file's: checked before the file is read,
// so that its error does not name the file.
void check_command_line_instance(const std::string& instance) {
  if (!instance.empty()) ipc::check_instance_name(instance);
}

}  // namespace

BridgeConfig parse_bridge_config(const std::string& text, const std::string& source,
                                 const std::string& instance) {
  check_command_line_instance(instance);
  return bridge_config_in(io::load_yaml_text(text, source), source, instance);
}

BridgeConfig load_bridge_config(const std::string& file, const std::string& instance) {
  check_command_line_instance(instance);
  return bridge_config_in(io::load_yaml_file(file), file, instance);
}

std::string describe_bridge(const BridgeConfig& config) {
  return "DDS domain " + std::to_string(config.domain_id) + ", publishing " +
         dds_topic_name(config.scan_topic) + " and " + dds_topic_name(config.diagnostics_topic) +
         " from " + config.socket_path;
}

}  // namespace tofcomp::bridges::ros2
