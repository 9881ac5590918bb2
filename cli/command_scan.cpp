// tofcomp scan DEVICE: brings up an LMS 200 (or the emulated one) with the host driver and
// prints the scans it streams: a check of a link before a daemon is pointed at it.
#include <fmt/format.h>

#include <boost/asio.hpp>
#include <cstdio>

#include "cli/command.hpp"
#include "cli/number_checks.hpp"
#include "core/error.hpp"
#include "hal/lms2xx/host_driver.hpp"

namespace tofcomp::cli {

namespace {

namespace lms = tofcomp::hal::lms2xx;

struct ScanOptions {
  std::string device;
  unsigned baud = 500000;
  std::string variant = "180:0.5";
  std::string units = "mm";
  int count = 10;
  double timeout_s = 30.0;
};

lms::Variant parse_variant(const std::string& text) {
  const auto colon = text.find(':');
  try {
    if (colon != std::string::npos) {
      const lms::Variant v{
          static_cast<std::uint16_t>(std::stoi(text.substr(0, colon))),
          static_cast<std::uint16_t>(std::stod(text.substr(colon + 1)) * 100 + 0.5)};
      if (v.is_valid()) return v;
    }
  } catch (const std::exception&) {
  }
  throw core::InvalidInput("--variant '" + text +
                           "': expected FIELD:RESOLUTION, one of 180:1, 180:0.5, 100:1, 100:0.5, "
                           "100:0.25");
}

CommandResult scan(const ScanOptions& o, const CommonOptions& common) {
  lms::DriverSettings settings;
  settings.device = o.device;
  settings.baud = o.baud;
  settings.variant = parse_variant(o.variant);
  if (o.units != "mm" && o.units != "cm") {
    throw core::InvalidInput("--units '" + o.units + "': expected mm or cm");
  }
  settings.units = o.units == "mm" ? lms::Units::Millimetre : lms::Units::Centimetre;
  boost::asio::io_context io;
  std::vector<lms::HostScan> scans;
  std::string last_state;
  lms::Lms2xxDriver driver(
      io, settings,
      [&](const lms::HostScan& s) {
        if (static_cast<int>(scans.size()) < o.count) scans.push_back(s);
        if (static_cast<int>(scans.size()) == o.count) io.stop();
      },
      [&](lms::LinkState state, const std::string& why) {
        last_state = lms::to_string(state) + ": " + why;
        if (!common.quiet) std::fprintf(stderr, "scan: %s\n", last_state.c_str());
      });
  driver.start();
  io.run_for(std::chrono::duration_cast<std::chrono::milliseconds>(
      std::chrono::duration<double>(o.timeout_s)));
  const lms::DriverCounters counters = driver.counters();
  if (static_cast<int>(scans.size()) < o.count) {
    throw core::Error(fmt::format("got {} of {} scans from {} in {:g} s; link {}", scans.size(),
                                  o.count, o.device, o.timeout_s, last_state));
  }
  CommandResult result;
  result.json["device"] = o.device;
  result.json["baud"] = o.baud;
  result.json["scans"] = nlohmann::json::array();
  std::string text;
  for (const auto& s : scans) {
    const std::size_t centre = s.scan.distance_codes.size() / 2;
    const auto status =
        lms::classify_distance_code(s.measuring_mode, s.scan.distance_codes[centre]);
    nlohmann::json row{{"sequence", s.sequence},
                       {"values", s.scan.distance_codes.size()},
                       {"units", lms::to_string(s.scan.units)},
                       {"codes", s.scan.distance_codes}};
    result.json["scans"].push_back(row);
    text += fmt::format("scan {}: {} values, centre {}\n", s.sequence, s.scan.distance_codes.size(),
                        status == lms::ValueStatus::Distance
                            ? fmt::format("{:g} mm", s.scan.distance_mm(centre))
                            : lms::to_string(status));
  }
  result.json["counters"] = {{"crc_errors", counters.decoder.crc_errors},
                             {"garbage_bytes", counters.decoder.garbage_bytes},
                             {"timeouts", counters.timeouts},
                             {"naks", counters.naks},
                             {"rate_searches", counters.rate_searches}};
  text +=
      fmt::format("link: {} CRC errors, {} garbage bytes, {} timeouts, {} NAKs, {} rate searches\n",
                  counters.decoder.crc_errors, counters.decoder.garbage_bytes, counters.timeouts,
                  counters.naks, counters.rate_searches);
  result.text = text;
  return result;
}

}  // namespace

void register_scan(CLI::App& app, const CommonOptions& common, CommandRunner& run) {
  auto* cmd = app.add_subcommand(
      "scan", "Bring up an LMS 200 on a serial port (or an emulated one) and print its scans");
  auto o = std::make_shared<ScanOptions>();
  cmd->add_option("device", o->device, "Serial port, e.g. /dev/ttyUSB0 or emulate's path")
      ->required();
  cmd->add_option("--baud", o->baud, "Rate to run the link at")
      ->check(CLI::IsMember({9600u, 19200u, 38400u, 500000u}))
      ->capture_default_str();
  cmd->add_option("--variant", o->variant, "Field and resolution in degrees")
      ->capture_default_str()
      ->type_name("FIELD:STEP");
  cmd->add_option("--units", o->units, "Range units: mm (8 m mode) or cm (80 m)")
      ->capture_default_str()
      ->type_name("UNITS");
  cmd->add_option("-n,--count", o->count, "Scans to print")
      ->check(at_least(1))
      ->capture_default_str();
  cmd->add_option("--timeout", o->timeout_s, "Give up after this many seconds")
      ->check(greater_than(0))
      ->capture_default_str();
  cmd->callback([&common, &run, o] { run = [&common, o] { return scan(*o, common); }; });
}

}  // namespace tofcomp::cli
