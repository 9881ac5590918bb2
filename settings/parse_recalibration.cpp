// Reader of the `recalibration` section: where a new calibration comes from (a recorded data
// set with a known distance, or a calibration run that cycles the scanner's power, §8.1), when
// it is made, and where it goes.
#include <array>
#include <string>
#include <string_view>
#include <utility>

#include "io/yaml_typed_fields.hpp"
#include "settings/section_parsers.hpp"

namespace tofcomp::settings::sections {

namespace {

using io::fields::between;
using io::fields::greater_than_up_to;

// The sub-section each source reads its own settings from.
constexpr std::array<std::pair<RecalibrationSource, std::string_view>, 2> kSourceSections = {{
    {RecalibrationSource::Recording, "recording"},
    {RecalibrationSource::PowerCycleRun, "power_cycle_run"},
}};

void parse_power_cycle_run(const io::YamlMap& map, const ParseContext& context,
                           PowerCycleRunConfig& out) {
  out.cycles = static_cast<int>(io::fields::integer(map, "cycles", between(1, 1000), out.cycles));
  out.on_s = io::fields::number(map, "on_s", greater_than_up_to(0, 86400), out.on_s);
  out.off_s = io::fields::number(map, "off_s", greater_than_up_to(0, 86400), out.off_s);
  out.true_range_mm = io::fields::required_number(map, "true_range_mm", greater_than_up_to(0, 100000));
  const io::YamlMap beams(map.node("beams"), map.child_path("beams"), {"first", "last"});
  out.beams.first = static_cast<int>(io::fields::required_integer(beams, "first", between(0, 400)));
  out.beams.last =
      static_cast<int>(io::fields::integer(beams, "last", between(0, 400), out.beams.first));
  if (out.beams.last < out.beams.first) {
    beams.fail("last", "must be at least " + map.child_path("beams") + ".first (" +
                           std::to_string(out.beams.first) + "), not " +
                           std::to_string(out.beams.last));
  }
  out.recording = io::fields::required_path(map, "recording", context.base_directory);
}

void parse_limits(const io::YamlMap& map, RecalibrationLimits& out) {
  out.time = std::chrono::seconds(
      io::fields::integer(map, "time_s", between(1, static_cast<double>(kLargestTrainingTime.count())),
                      static_cast<long>(out.time.count())));
  out.memory_mib = static_cast<std::uint64_t>(
      io::fields::integer(map, "memory_mib",
                      between(static_cast<double>(kSmallestTrainingMemoryMib),
                              static_cast<double>(kLargestTrainingMemoryMib)),
                      static_cast<long>(out.memory_mib)));
  out.recording_mib = static_cast<std::uint64_t>(
      io::fields::integer(map, "recording_mib", between(1, static_cast<double>(kLargestRecordingMib)),
                      static_cast<long>(out.recording_mib)));
}

}  // namespace

void parse_recalibration(const io::YamlMap& root, const ParseContext& context,
                         const CalibrationConfig& calibration, RecalibrationConfig& out) {
  out.output = calibration.file;
  const auto map = io::fields::section(
      root, "recalibration",
      {"source", "trigger", "datasheet", "output", "recording", "power_cycle_run", "limits",
       "model_search"});
  if (!map) return;
  out.source =
      io::fields::choice<RecalibrationSource>(*map, "source",
                                          {{"none", RecalibrationSource::None},
                                           {"recording", RecalibrationSource::Recording},
                                           {"power_cycle_run", RecalibrationSource::PowerCycleRun}},
                                          out.source);
  for (const auto& [source, key] : kSourceSections) {
    if (source != out.source && map->has(key)) {
      map->fail(key, "applies to source " + std::string(key) + " only; source is " +
                         to_string(out.source));
    }
  }
  out.trigger = io::fields::choice<RecalibrationTrigger>(
      *map, "trigger",
      {{"on_request", RecalibrationTrigger::OnRequest},
       {"at_start_if_missing", RecalibrationTrigger::AtStartIfMissing}},
      out.trigger);
  // Left out: the LMS 200 datasheet built in (io/bundled_datasheet.hpp).
  out.datasheet = io::fields::path(*map, "datasheet", context.base_directory, {});
  out.output = io::fields::path(*map, "output", context.base_directory, out.output);
  out.model_search = map->boolean_or("model_search", out.model_search);
  if (const auto limits =
          io::fields::section(*map, "limits", {"time_s", "memory_mib", "recording_mib"})) {
    parse_limits(*limits, out.limits);
  }
  if (out.source == RecalibrationSource::Recording) {
    const io::YamlMap recording(map->node("recording"), map->child_path("recording"),
                                {"data", "directory"});
    out.data = io::fields::required_path(recording, "data", context.base_directory);
    out.recordings_directory =
        io::fields::path(recording, "directory", context.base_directory, out.data.parent_path());
  } else if (out.source == RecalibrationSource::PowerCycleRun) {
    const io::YamlMap run(map->node("power_cycle_run"), map->child_path("power_cycle_run"),
                          {"cycles", "on_s", "off_s", "true_range_mm", "beams", "recording"});
    parse_power_cycle_run(run, context, out.power_cycle_run);
  }
}

}  // namespace tofcomp::settings::sections
