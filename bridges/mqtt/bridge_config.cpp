// Reading the bridge's configuration strictly (io/yaml_typed_fields.hpp underneath).
#include "bridges/mqtt/bridge_config.hpp"

#include <yaml-cpp/yaml.h>

#include "core/error.hpp"
#include "io/checked_file.hpp"
#include "io/yaml_fields.hpp"
#include "io/yaml_typed_fields.hpp"
#include "ipc/instance_name.hpp"
#include "tofcomp/tofcomp_client.h"

namespace tofcomp::bridges::mqtt {

namespace {

using io::fields::between;

// No configuration of the bridge comes near these: beyond either it is refused before it costs.
constexpr io::YamlShapeLimits kConfigShapeLimits{.max_depth = 8, .max_values = 1000};
constexpr std::uint64_t kMaxConfigBytes = 64u * 1024u;
constexpr int kDefaultPlainPort = 1883;
constexpr int kDefaultTlsPort = 8883;
// MQTT 3.1.1 allows client ids of up to 23 bytes for certain; brokers (mosquitto among them)
// take longer ones, up to this.
constexpr std::size_t kMaxClientIdBytes = 128;
constexpr std::size_t kMaxUsernameBytes = 256;

// A topic level the bridge names (site, instance, prefix): the instance names' rule (letters,
// digits, '-' and '_'), which keeps MQTT's wildcards '+' and '#' and the separator '/' out.
std::string topic_level(const io::YamlMap& map, std::string_view key, std::string fallback) {
  std::string value = io::fields::text(map, key, std::move(fallback));
  if (const std::string problem = ipc::instance_name_problem(value); !problem.empty()) {
    map.fail(key, "is no topic name: " + problem);
  }
  return value;
}

Backoff read_backoff(const io::YamlMap& root) {
  Backoff out;
  if (const auto map = io::fields::section(root, "reconnect", {"initial_s", "max_s"})) {
    out.initial = std::chrono::seconds(
        io::fields::integer(*map, "initial_s", between(1, 600), out.initial.count()));
    out.max =
        std::chrono::seconds(io::fields::integer(*map, "max_s", between(1, 3600), out.max.count()));
    if (out.max < out.initial) map->fail("max_s", "must be at least reconnect.initial_s");
  }
  return out;
}

std::optional<TlsSettings> read_tls(const io::YamlMap& broker, const std::filesystem::path& base) {
  const auto map =
      io::fields::section(broker, "tls", {"ca_file", "cert_file", "key_file", "verify_hostname"});
  if (!map) return std::nullopt;
  TlsSettings tls;
  tls.ca_file = io::fields::required_path(*map, "ca_file", base);
  if (map->has("cert_file")) tls.cert_file = io::fields::required_path(*map, "cert_file", base);
  if (map->has("key_file")) tls.key_file = io::fields::required_path(*map, "key_file", base);
  if (tls.cert_file.has_value() != tls.key_file.has_value()) {
    map->fail(tls.cert_file ? "key_file" : "cert_file",
              "is missing: a client certificate needs both cert_file and key_file");
  }
  tls.verify_hostname = map->boolean_or("verify_hostname", true);
  return tls;
}

BrokerSettings read_broker(const io::YamlMap& root, const std::filesystem::path& base) {
  const io::YamlMap map(root.node("broker"), "broker",
                        {"host", "port", "client_id", "keepalive_s", "username", "password_file",
                         "tls"});
  BrokerSettings out;
  out.host = io::fields::required_text(map, "host");
  out.tls = read_tls(map, base);
  out.port = static_cast<int>(io::fields::integer(map, "port", between(1, 65535),
                                                  out.tls ? kDefaultTlsPort : kDefaultPlainPort));
  out.client_id = io::fields::text(map, "client_id", "");
  if (out.client_id.size() > kMaxClientIdBytes) {
    map.fail("client_id", "must be at most " + std::to_string(kMaxClientIdBytes) + " bytes");
  }
  out.keepalive = std::chrono::seconds(
      io::fields::integer(map, "keepalive_s", between(5, 3600), out.keepalive.count()));
  if (map.has("username")) {
    out.username = io::fields::required_text(map, "username");
    if (out.username->size() > kMaxUsernameBytes) {
      map.fail("username", "must be at most " + std::to_string(kMaxUsernameBytes) + " bytes");
    }
  }
  if (map.has("password_file")) {
    if (!out.username) map.fail("password_file", "needs broker.username");
    out.password_file = io::fields::required_path(map, "password_file", base);
  }
  return out;
}

PublishPeriods read_publish(const io::YamlMap& root) {
  PublishPeriods out;
  const auto map = io::fields::section(
      root, "publish", {"status_ms", "junction_ms", "diagnosis_ms", "ranges_ms", "ranges_beam_step"});
  if (!map) return out;
  // At most half tofcompd's idle_timeout_s (60 s by default): the status requests keep the
  // control connection open.
  out.status = io::fields::milliseconds(*map, "status_ms", between(100, 30000), out.status);
  out.junction = io::fields::milliseconds(*map, "junction_ms", between(0, 3600000), out.junction);
  out.diagnosis =
      io::fields::milliseconds(*map, "diagnosis_ms", between(100, 3600000), out.diagnosis);
  out.ranges = io::fields::milliseconds(*map, "ranges_ms", between(100, 3600000), out.ranges);
  out.ranges_beam_step =
      static_cast<int>(io::fields::integer(*map, "ranges_beam_step", between(1, 1024), 1));
  return out;
}

CommandPermissions read_commands(const io::YamlMap& root) {
  CommandPermissions out;
  if (const auto map = io::fields::section(root, "commands", {"reload", "recalibrate"})) {
    out.reload = map->boolean_or("reload", false);
    out.recalibrate = map->boolean_or("recalibrate", false);
  }
  return out;
}

BridgeConfig read_document(const YAML::Node& document, const std::filesystem::path& base,
                           const std::string& instance) {
  const io::YamlMap root(document, "",
                         {"broker", "topic_prefix", "site", "instance", "tofcompd", "reconnect",
                          "publish", "commands"});
  BridgeConfig out;
  out.broker = read_broker(root, base);
  out.topic_prefix = topic_level(root, "topic_prefix", out.topic_prefix);
  if (!root.has("site")) root.fail("site", "is missing");
  out.site = topic_level(root, "site", "");
  out.instance = topic_level(root, "instance", instance.empty() ? out.instance : instance);
  if (!instance.empty() && out.instance != instance) {
    root.fail("instance", "is '" + out.instance + "', but --instance names '" + instance + "'");
  }
  std::filesystem::path socket = instance.empty()
                                     ? std::filesystem::path(TOFCOMP_DEFAULT_SOCKET_PATH)
                                     : std::filesystem::path(ipc::instance_socket_path(instance));
  if (const auto map = io::fields::section(root, "tofcompd", {"socket"})) {
    socket = io::fields::path(*map, "socket", base, socket);
  }
  out.tofcompd_socket = socket.string();
  out.reconnect = read_backoff(root);
  out.publish = read_publish(root);
  out.commands = read_commands(root);
  if (out.broker.client_id.empty()) {
    out.broker.client_id = out.topic_prefix + "-" + out.site + "-" + out.instance;
  }
  return out;
}

}  // namespace

BridgeConfig parse_bridge_config(const std::string& text, const std::string& source,
                                 const std::filesystem::path& base, const std::string& instance) {
  try {
    YAML::Node document = io::load_yaml_text(text, source, kConfigShapeLimits);
    if (document.IsNull()) document = YAML::Node(YAML::NodeType::Map);
    BridgeConfig config = read_document(document, base, instance);
    config.source = source;
    return config;
  } catch (const io::YamlSchemaError& e) {
    const std::string what = e.what();
    // load_yaml_text's own errors start with the source; the readers' with the key path.
    throw core::InvalidInput(what.rfind(source, 0) == 0 ? what : source + ": " + what);
  } catch (const YAML::Exception& e) {
    throw core::InvalidInput(io::yaml_position(source, e.mark) + ": " + e.msg);
  } catch (const core::Error& e) {
    throw core::InvalidInput(source + ": " + e.what());
  }
}

BridgeConfig read_bridge_config(const std::filesystem::path& file, const std::string& instance) {
  const std::string source = file.string();
  const io::CheckedFile checked =
      io::open_checked_file(file, kMaxConfigBytes, "configuration", "the largest configuration");
  const std::string text =
      io::read_checked_file(checked, kMaxConfigBytes, "configuration", "the largest configuration");
  return parse_bridge_config(text, source, std::filesystem::absolute(file).parent_path(), instance);
}

}  // namespace tofcomp::bridges::mqtt
