// One reader per section of tofcompd.yaml, each filling its part of DaemonConfig from the
// document's top-level mapping (absent sections keep their defaults). Internal to the reader;
// each throws io::YamlSchemaError naming the key path.
#pragma once

#include <filesystem>

#include "io/yaml_fields.hpp"
#include "ipc/default_places.hpp"
#include "settings/daemon_config.hpp"

namespace tofcomp::settings::sections {

// What every section reader needs besides its mapping.
struct ParseContext {
  std::filesystem::path base_directory;  // relative paths are resolved against it
  ipc::DaemonPlaces places;  // the defaults of the socket, the ring and the recordings' folder
};

void parse_link(const io::YamlMap& root, const ParseContext& context, LinkConfig& out);
void parse_emulator(const io::YamlMap& root, const ParseContext& context, EmulatorConfig& out);
void parse_case_sensor(const io::YamlMap& root, const ParseContext& context, CaseSensorConfig& out);
void parse_power(const io::YamlMap& root, PowerConfig& out);
void parse_calibration(const io::YamlMap& root, const ParseContext& context,
                       CalibrationConfig& out);
void parse_compensation(const io::YamlMap& root, CompensationConfig& out);
void parse_outputs(const io::YamlMap& root, const ParseContext& context, OutputsConfig& out);
void parse_recording(const io::YamlMap& root, const ParseContext& context, RecordingConfig& out);
// After parse_calibration: `output` defaults to calibration.file.
void parse_recalibration(const io::YamlMap& root, const ParseContext& context,
                         const CalibrationConfig& calibration, RecalibrationConfig& out);
void parse_log(const io::YamlMap& root, LogConfig& out);

}  // namespace tofcomp::settings::sections
