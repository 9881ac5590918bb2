// tofcomp-mqtt-bridge's configuration (docs/integration.md, "Fleet telemetry over MQTT"): the
// broker and how to reach it (TLS, credentials), the names of its topics (site, instance), the
// tofcompd socket it reads, the rates it publishes at, and which remote commands it passes on.
// Read strictly: an unknown key, a value of the wrong type or out of its range is an error naming
// the file, the key path and what was expected.
#pragma once

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>

namespace tofcomp::bridges::mqtt {

struct TlsSettings {
  std::filesystem::path ca_file;                 // the CA that signed the broker's certificate
  std::optional<std::filesystem::path> cert_file;  // a client certificate (with key_file)
  std::optional<std::filesystem::path> key_file;
  bool verify_hostname = true;  // the broker's certificate must name the host connected to
};

// Reconnection to the broker and to tofcompd: the first wait after a loss, doubled at each
// failed try up to max (libmosquitto counts whole seconds).
struct Backoff {
  std::chrono::seconds initial{1};
  std::chrono::seconds max{60};
};

struct BrokerSettings {
  std::string host;
  int port = 1883;  // 8883 when tls is set and port is not
  std::string client_id;
  std::chrono::seconds keepalive{30};
  std::optional<std::string> username;
  std::optional<std::filesystem::path> password_file;  // the password itself is never logged
  std::optional<TlsSettings> tls;
};

struct PublishPeriods {
  std::chrono::milliseconds status{5000};
  std::chrono::milliseconds junction{1000};
  std::chrono::milliseconds diagnosis{10000};
  std::chrono::milliseconds ranges{5000};
  int ranges_beam_step = 1;  // every nth beam in the range summary
};

// Which control requests of the command topic are passed to tofcompd. Both off by default.
struct CommandPermissions {
  bool reload = false;
  bool recalibrate = false;
};

struct BridgeConfig {
  std::string source;  // the file read, for messages
  BrokerSettings broker;
  std::string topic_prefix = "tofcomp";
  std::string site;
  std::string instance = "default";
  std::string tofcompd_socket;
  Backoff reconnect;
  PublishPeriods publish;
  CommandPermissions commands;
};

// Reads and checks `file`. `instance` is the command line's --instance (empty when not given):
// the default of `instance` and of `tofcompd.socket` (the instance's socket); a configuration
// naming another instance is an error. Throws io::YamlSchemaError or core::InvalidInput naming
// the key.
BridgeConfig read_bridge_config(const std::filesystem::path& file, const std::string& instance);
// The same for text in memory (the tests); `source` names it, relative paths are resolved
// against `base`.
BridgeConfig parse_bridge_config(const std::string& text, const std::string& source,
                                 const std::filesystem::path& base, const std::string& instance);

}  // namespace tofcomp::bridges::mqtt
