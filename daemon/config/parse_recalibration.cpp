// Reader of the `recalibration` section: where a new calibration comes from (a recorded data
// set with a known distance), when it is made, and where it goes.
#include <string>

#include "daemon/config/config_fields.hpp"
#include "daemon/config/section_parsers.hpp"

namespace tofcomp::daemon::config::sections {

void parse_recalibration(const io::YamlMap& root, const ParseContext& context,
                         const CalibrationConfig& calibration, RecalibrationConfig& out) {
  out.output = calibration.file;
  const auto map = fields::section(root, "recalibration",
                                   {"source", "trigger", "datasheet", "output", "recording"});
  if (!map) return;
  out.source = fields::choice<RecalibrationSource>(
      *map, "source",
      {{"none", RecalibrationSource::None}, {"recording", RecalibrationSource::Recording}},
      out.source);
  if (out.source != RecalibrationSource::Recording && map->has("recording")) {
    map->fail("recording", "applies to source recording only; source is " + to_string(out.source));
  }
  out.trigger = fields::choice<RecalibrationTrigger>(
      *map, "trigger",
      {{"on_request", RecalibrationTrigger::OnRequest},
       {"at_start_if_missing", RecalibrationTrigger::AtStartIfMissing}},
      out.trigger);
  out.datasheet = out.source == RecalibrationSource::None
                      ? fields::path(*map, "datasheet", context.base_directory, {})
                      : fields::required_path(*map, "datasheet", context.base_directory);
  out.output = fields::path(*map, "output", context.base_directory, out.output);
  if (out.source == RecalibrationSource::Recording) {
    const io::YamlMap recording(map->node("recording"), map->child_path("recording"), {"data"});
    out.data = fields::required_path(recording, "data", context.base_directory);
  }
}

}  // namespace tofcomp::daemon::config::sections
