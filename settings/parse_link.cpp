// Readers of the `link` section (the serial link to the LMS 200) and the `emulator` section
// (the emulated LMS 200 served in-process).
#include "io/yaml_typed_fields.hpp"
#include "settings/section_parsers.hpp"

namespace tofcomp::settings::sections {

namespace {

using io::fields::at_least;
using io::fields::between;
using io::fields::greater_than_up_to;

namespace lms = hal::lms2xx;

lms::Variant parse_variant(const io::YamlMap& map, lms::Variant fallback) {
  const long field = io::fields::integer_choice(map, "field_deg", {180, 100}, fallback.angle_deg);
  const double resolution = io::fields::number_choice(map, "resolution_deg", {1.0, 0.5, 0.25},
                                                  fallback.resolution_centideg / 100.0);
  // Whether this resolution exists with this field is validate()'s to say.
  return lms::Variant{static_cast<std::uint16_t>(field),
                      static_cast<std::uint16_t>(resolution * 100.0)};
}

}  // namespace

void parse_link(const io::YamlMap& root, const ParseContext& context, LinkConfig& out) {
  const auto link = io::fields::section(
      root, "link",
      {"device", "baud", "variant", "units", "measuring_mode", "timeouts", "attempts", "backoff"});
  if (!link) return;
  out.device = io::fields::path(*link, "device", context.base_directory, out.device);
  out.baud = static_cast<unsigned>(
      io::fields::integer_choice(*link, "baud", {9600, 19200, 38400, 500000}, out.baud));
  if (const auto variant = io::fields::section(*link, "variant", {"field_deg", "resolution_deg"})) {
    out.variant = parse_variant(*variant, out.variant);
  }
  out.units = io::fields::choice<lms::Units>(
      *link, "units", {{"mm", lms::Units::Millimetre}, {"cm", lms::Units::Centimetre}}, out.units);
  out.measuring_mode = io::fields::choice<lms::MeasuringMode>(*link, "measuring_mode",
                                                          {{"8m", lms::MeasuringMode::Range8m},
                                                           {"16m", lms::MeasuringMode::Range16m},
                                                           {"32m", lms::MeasuringMode::Range32m}},
                                                          out.measuring_mode);
  if (const auto timeouts = io::fields::section(*link, "timeouts", {"ack_ms", "reply_ms", "scan_ms"})) {
    out.ack_timeout = io::fields::milliseconds(*timeouts, "ack_ms", between(1, 60000), out.ack_timeout);
    out.reply_timeout =
        io::fields::milliseconds(*timeouts, "reply_ms", between(1, 60000), out.reply_timeout);
    out.scan_timeout =
        io::fields::milliseconds(*timeouts, "scan_ms", between(10, 600000), out.scan_timeout);
  }
  out.attempts =
      static_cast<int>(io::fields::integer(*link, "attempts", between(1, 100), out.attempts));
  if (const auto backoff = io::fields::section(*link, "backoff", {"initial_ms", "max_ms"})) {
    out.backoff_initial =
        io::fields::milliseconds(*backoff, "initial_ms", between(1, 600000), out.backoff_initial);
    out.backoff_max =
        io::fields::milliseconds(*backoff, "max_ms", between(1, 3600000), out.backoff_max);
  }
}

namespace {

void parse_faults(const io::YamlMap& map, sim::lms200::FaultRates& out) {
  const auto rate = [&map](std::string_view key, double fallback) {
    return io::fields::number(map, key, between(0, 1), fallback);
  };
  out.garbage = rate("garbage", out.garbage);
  out.dropped_byte = rate("dropped_byte", out.dropped_byte);
  out.corrupted_crc = rate("corrupted_crc", out.corrupted_crc);
  out.stall = rate("stall", out.stall);
  out.hang_up = rate("hang_up", out.hang_up);
  out.reset = rate("reset", out.reset);
  out.stall_s = io::fields::number(map, "stall_s", greater_than_up_to(0, 3600), out.stall_s);
  out.max_garbage_bytes = static_cast<int>(
      io::fields::integer(map, "max_garbage_bytes", between(1, 1024), out.max_garbage_bytes));
}

}  // namespace

void parse_emulator(const io::YamlMap& root, const ParseContext& context, EmulatorConfig& out) {
  const auto emulator = io::fields::section(
      root, "emulator",
      {"enabled", "scenario", "recording", "time_scale", "faults", "fault_seed", "link", "rs232"});
  if (!emulator) return;
  out.enabled = emulator->boolean_or("enabled", out.enabled);
  out.scenario = out.enabled ? io::fields::required_path(*emulator, "scenario", context.base_directory)
                             : io::fields::path(*emulator, "scenario", context.base_directory, {});
  out.recording = io::fields::path(*emulator, "recording", context.base_directory, {});
  out.time_scale = io::fields::number(*emulator, "time_scale", between(0, 1e6), out.time_scale);
  if (const auto faults = io::fields::section(*emulator, "faults",
                                          {"garbage", "dropped_byte", "corrupted_crc", "stall",
                                           "hang_up", "reset", "stall_s", "max_garbage_bytes"})) {
    parse_faults(*faults, out.faults);
  }
  out.fault_seed = static_cast<std::uint64_t>(
      io::fields::integer(*emulator, "fault_seed", at_least(0), static_cast<long>(out.fault_seed)));
  out.link = io::fields::path(*emulator, "link", context.base_directory, out.link);
  out.rs232 = emulator->boolean_or("rs232", out.rs232);
}

}  // namespace tofcomp::settings::sections
