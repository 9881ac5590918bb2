// Readers of the `outputs` section (the Unix socket and the shared-memory ring), the
// `recording` section (the interchange CSV of what was measured) and the `log` section.
#include <string>

#include "core/error.hpp"
#include "io/yaml_typed_fields.hpp"
#include "settings/output_checks.hpp"
#include "settings/section_parsers.hpp"

namespace tofcomp::settings::sections {

namespace {

using io::fields::between;

void parse_socket(const io::YamlMap& map, const ParseContext& context, SocketOutputConfig& out) {
  out.path = io::fields::path(map, "path", context.base_directory, out.path);
  if (const std::string problem = socket_path_problem(out.path); !problem.empty()) {
    map.fail("path", problem);
  }
  out.mode = io::fields::octal_mode(map, "mode", out.mode);
  namespace limits = ipc::socket;
  out.max_clients = static_cast<int>(io::fields::integer(
      map, "max_clients", between(1, static_cast<double>(limits::kLargestMaxClients)),
      out.max_clients));
  out.max_request_bytes = static_cast<std::size_t>(
      io::fields::integer(map, "max_request_bytes",
                      between(static_cast<double>(limits::kSmallestMaxRequestBytes),
                              static_cast<double>(limits::kLargestMaxRequestBytes)),
                      static_cast<long>(out.max_request_bytes)));
  out.max_queued_bytes_per_client = static_cast<std::size_t>(
      io::fields::integer(map, "max_queued_bytes_per_client",
                      between(static_cast<double>(limits::kSmallestMaxQueuedBytesPerClient),
                              static_cast<double>(limits::kLargestMaxQueuedBytesPerClient)),
                      static_cast<long>(out.max_queued_bytes_per_client)));
  out.idle_timeout = std::chrono::seconds(io::fields::integer(
      map, "idle_timeout_s", between(1, static_cast<double>(limits::kLargestIdleTimeout.count())),
      static_cast<long>(out.idle_timeout.count())));
}

void parse_shm(const io::YamlMap& map, ShmOutputConfig& out) {
  if (map.has("name")) {
    const std::string name = map.text("name");
    if (const std::string problem = shm_name_problem(name); !problem.empty()) {
      map.fail("name", problem);
    }
    out.name = name;
  }
  out.slots = static_cast<int>(io::fields::integer(map, "slots", between(2, 1 << 20), out.slots));
  out.mode = io::fields::octal_mode(map, "mode", out.mode);
}

}  // namespace

void parse_outputs(const io::YamlMap& root, const ParseContext& context, OutputsConfig& out) {
  const auto outputs = io::fields::section(root, "outputs", {"socket", "shm"});
  if (!outputs) return;
  if (const auto socket = io::fields::section(*outputs, "socket",
                                          {"path", "mode", "max_clients", "max_request_bytes",
                                           "max_queued_bytes_per_client", "idle_timeout_s"})) {
    parse_socket(*socket, context, out.socket);
  }
  if (const auto shm = io::fields::section(*outputs, "shm", {"name", "slots", "mode"})) {
    parse_shm(*shm, out.shm);
  }
}

void parse_recording(const io::YamlMap& root, const ParseContext& context, RecordingConfig& out) {
  const auto recording = io::fields::section(root, "recording", {"enabled", "directory", "rotation"});
  if (!recording) return;
  out.enabled = recording->boolean_or("enabled", out.enabled);
  out.directory = io::fields::path(*recording, "directory", context.base_directory, out.directory);
  if (const auto rotation = io::fields::section(*recording, "rotation", {"max_rows", "max_minutes"})) {
    // Given, the section lists every limit in force: one left out is no limit.
    out.max_rows = io::fields::optional_integer(*rotation, "max_rows", between(1, 1e12));
    out.max_minutes = io::fields::optional_integer(*rotation, "max_minutes", between(1, 525600));
    if (!out.max_rows && !out.max_minutes) {
      throw io::YamlSchemaError(rotation->path() + " must give max_rows, max_minutes or both");
    }
  }
}

void parse_log(const io::YamlMap& root, LogConfig& out) {
  const auto log = io::fields::section(root, "log", {"level", "target"});
  if (!log) return;
  // The names are the logging module's own, so that they cannot drift apart.
  try {
    if (log->has("level")) out.level = parse_log_level(log->text("level"));
  } catch (const core::InvalidInput& e) {
    log->fail("level", std::string("is not valid: ") + e.what());
  }
  try {
    if (log->has("target")) out.target = parse_log_target(log->text("target"));
  } catch (const core::InvalidInput& e) {
    log->fail("target", std::string("is not valid: ") + e.what());
  }
}

}  // namespace tofcomp::settings::sections
