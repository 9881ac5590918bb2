// Reading tofcompd.yaml: the text to a YAML document (syntax errors with line and column), the
// document's shape (no key given twice, only text keys), then each section's reader, then
// validate(). Every failure leaves as one DaemonConfigError starting with the source.
#include "settings/daemon_config_yaml.hpp"

#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <cstring>
#include <fstream>

#include "io/checked_file.hpp"
#include "io/yaml_fields.hpp"
#include "settings/section_parsers.hpp"

namespace tofcomp::settings {

namespace {

// No key of the schema is deeper than this, and no configuration holds this many values: the
// shape check stops with an error beyond either, so that a deeply nested, self-referencing or
// alias-multiplied document ("billion laughs") costs little.
constexpr io::YamlShapeLimits kConfigShapeLimits{.max_depth = 16, .max_values = 100000};
constexpr std::uint64_t kMaxConfigBytes = 1u << 20;
// recording.directory's default under the state directory.
constexpr const char* kRecordingsFolder = "recordings";

// The text to one document, strictly (io::load_yaml_text: one document, no NUL, no key twice,
// only text keys, within the limits); an empty configuration is an empty mapping.
YAML::Node parse_document(std::string_view text, const std::string& source) {
  YAML::Node document;
  try {
    document = io::load_yaml_text(std::string(text), source, kConfigShapeLimits);
  } catch (const io::YamlSchemaError& e) {
    throw DaemonConfigError(e.what());
  }
  if (document.IsNull()) return YAML::Node(YAML::NodeType::Map);
  return document;
}

DaemonConfig read_sections(const YAML::Node& document, const sections::ParseContext& context) {
  const io::YamlMap root(document, "",
                         {"link", "emulator", "case_sensor", "power", "calibration", "compensation",
                          "outputs", "recording", "recalibration", "log"});
  DaemonConfig config;
  config.outputs.socket.path = context.places.socket;
  config.outputs.shm.name = context.places.ring;
  config.recording.directory = context.places.state_directory / kRecordingsFolder;
  sections::parse_link(root, context, config.link);
  sections::parse_emulator(root, context, config.emulator);
  sections::parse_case_sensor(root, context, config.case_sensor);
  sections::parse_power(root, config.power);
  sections::parse_calibration(root, context, config.calibration);
  sections::parse_compensation(root, config.compensation);
  sections::parse_outputs(root, context, config.outputs);
  sections::parse_recording(root, context, config.recording);
  sections::parse_recalibration(root, context, config.calibration, config.recalibration);
  sections::parse_log(root, config.log);
  // The emulator's link path is where the driver finds the emulated device.
  if (config.emulator.enabled && config.link.device.empty()) {
    config.link.device = config.emulator.link;
  }
  return config;
}

}  // namespace

ipc::DaemonPlaces default_places_for_this_user() {
  return ipc::daemon_places(ipc::current_user_environment());
}

DaemonConfig parse_daemon_config(std::string_view text, const std::string& source_name,
                                 const std::filesystem::path& base_directory,
                                 const ipc::DaemonPlaces& places) {
  try {
    const sections::ParseContext context{
        std::filesystem::absolute(base_directory.empty() ? std::filesystem::path(".")
                                                         : base_directory)
            .lexically_normal(),
        places};
    const YAML::Node document = parse_document(text, source_name);
    DaemonConfig config = read_sections(document, context);
    config.source = source_name;
    validate(config);
    return config;
  } catch (const DaemonConfigError&) {
    throw;
  } catch (const YAML::Exception& e) {
    // yaml-cpp's own conversions, should a node surprise the reader.
    throw DaemonConfigError(io::yaml_position(source_name, e.mark) + ": " + e.msg);
  } catch (const core::Error& e) {
    throw DaemonConfigError(source_name + ": " + e.what());
  } catch (const std::filesystem::filesystem_error& e) {
    throw DaemonConfigError(source_name + ": " + e.what());
  }
}

DaemonConfig load_daemon_config(const std::filesystem::path& file,
                                const ipc::DaemonPlaces& places) {
  const std::string source = file.string();
  std::string text;
  try {
    // A regular file (a FIFO would block the daemon), of a size no configuration comes near.
    const io::CheckedFile checked =
        io::open_checked_file(file, kMaxConfigBytes, "configuration", "the largest configuration");
    text = io::read_checked_file(checked, kMaxConfigBytes, "configuration",
                                 "the largest configuration");
  } catch (const core::Error& e) {
    throw DaemonConfigError(source + ": cannot be read: " + e.what());
  }
  std::filesystem::path base;
  try {
    base = std::filesystem::absolute(file).parent_path();
  } catch (const std::filesystem::filesystem_error& e) {
    throw DaemonConfigError(source + ": " + e.what());
  }
  return parse_daemon_config(text, source, base, places);
}

}  // namespace tofcomp::settings
