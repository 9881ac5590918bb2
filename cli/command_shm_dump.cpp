// tofcomp shm-dump [NAME]: prints the compensated scans tofcompd publishes to its shared-memory
// ring (docs/shm-ring.md): the newest scan (or the -n newest), or with --follow each new scan as
// it comes until SIGINT/SIGTERM or -n scans. Per scan: sequence, time, junction temperature;
// per beam: raw, compensated, window estimate and its standard deviation, flags.
#include <signal.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <thread>

#include "cli/command.hpp"
#include "core/error.hpp"
#include "io/utc_time.hpp"
#include "ipc/ring/ring_reader.hpp"

namespace tofcomp::cli {

namespace {

namespace ring = tofcomp::ipc::ring;

struct ShmDumpOptions {
  std::string name = ring::kDefaultRingName;
  bool follow = false;
  int count = 0;  // 0: the newest scan, or with --follow every scan until stopped
  std::string beams;
};

// Beams first..last (inclusive) of each scan; the whole scan when not given.
struct BeamRange {
  std::size_t first = 0;
  std::size_t last = static_cast<std::size_t>(-1);
};

BeamRange parse_beam_range(const std::string& text) {
  if (text.empty()) return {};
  const auto fail = [&] {
    throw core::InvalidInput("--beams '" + text +
                             "': expected FIRST:LAST, beam indices from 0 with FIRST <= LAST "
                             "(e.g. 170:190)");
  };
  const auto colon = text.find(':');
  if (colon == std::string::npos) fail();
  const auto index = [&](const std::string& part) {
    if (part.empty() || part.find_first_not_of("0123456789") != std::string::npos ||
        part.size() > 9) {
      fail();
    }
    return static_cast<std::size_t>(std::stoul(part));
  };
  const BeamRange range{index(text.substr(0, colon)), index(text.substr(colon + 1))};
  if (range.first > range.last) fail();
  return range;
}

// SIGINT and SIGTERM set a flag (restoring the previous handlers when done), so that --follow
// ends its loop and the scans printed so far are summarised.
class StopOnSignal {
 public:
  StopOnSignal() {
    stop_requested().store(false);
    struct sigaction action {};
    action.sa_handler = [](int) { stop_requested().store(true); };
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &previous_int_);
    sigaction(SIGTERM, &action, &previous_term_);
  }
  ~StopOnSignal() {
    sigaction(SIGINT, &previous_int_, nullptr);
    sigaction(SIGTERM, &previous_term_, nullptr);
  }
  StopOnSignal(const StopOnSignal&) = delete;
  StopOnSignal& operator=(const StopOnSignal&) = delete;
  bool requested() const { return stop_requested().load(); }

 private:
  static std::atomic<bool>& stop_requested() {
    static std::atomic<bool> flag{false};
    static_assert(std::atomic<bool>::is_always_lock_free);
    return flag;
  }
  struct sigaction previous_int_ {};
  struct sigaction previous_term_ {};
};

// NaN (a value that does not exist; the flags say why) as JSON null.
nlohmann::json number_or_null(double value) {
  return std::isnan(value) ? nlohmann::json(nullptr) : nlohmann::json(value);
}

std::string format_or_dash(const char* format, double value) {
  if (std::isnan(value)) return "-";
  char text[48];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

std::string joined(const std::vector<std::string>& names) {
  if (names.empty()) return "-";
  std::string text;
  for (const auto& n : names) text += (text.empty() ? "" : ",") + n;
  return text;
}

double beam_angle_deg(const ipc::CompensatedScan& scan, std::size_t beam) {
  return scan.start_angle_deg + scan.resolution_deg * static_cast<double>(beam);
}

nlohmann::json scan_json(const ipc::CompensatedScan& scan, const BeamRange& range) {
  nlohmann::json beams = nlohmann::json::array();
  for (std::size_t b = range.first; b < scan.beams.size() && b <= range.last; ++b) {
    const ipc::BeamValue& v = scan.beams[b];
    beams.push_back({{"index", b},
                     {"angle_deg", beam_angle_deg(scan, b)},
                     {"raw_mm", number_or_null(v.raw_mm)},
                     {"compensated_mm", number_or_null(v.compensated_mm)},
                     {"window_mm", number_or_null(v.window_mm)},
                     {"window_std_mm", number_or_null(v.window_std_mm)},
                     {"mode_posterior", v.mode_posterior},
                     {"mode_count", v.mode_count},
                     {"most_probable_mode", v.most_probable_mode},
                     {"flags", v.flags},
                     {"flag_names", ipc::beam_flag_names(v.flags)}});
  }
  return {{"sequence", scan.sequence},
          {"device_sequence", scan.device_sequence},
          {"timestamp_ns", scan.timestamp_ns},
          {"time", io::utc_timestamp(scan.timestamp_ns, io::kMaxFractionDigits)},
          {"junction_c", number_or_null(scan.junction_c)},
          {"junction_std_c", number_or_null(scan.junction_std_c)},
          {"case_c", number_or_null(scan.case_c)},
          {"calibration_id", scan.calibration_id},
          {"start_angle_deg", scan.start_angle_deg},
          {"resolution_deg", scan.resolution_deg},
          {"beam_count", scan.beams.size()},
          {"beams", beams}};
}

std::string scan_text(const ipc::CompensatedScan& scan, const BeamRange& range) {
  char line[256];
  std::snprintf(line, sizeof line,
                "scan %llu (device %llu)  %s  junction %s ± %s °C  case %s °C  calibration %u  "
                "%zu beams\n",
                static_cast<unsigned long long>(scan.sequence),
                static_cast<unsigned long long>(scan.device_sequence),
                io::utc_timestamp(scan.timestamp_ns, io::kMaxFractionDigits).c_str(),
                format_or_dash("%.2f", scan.junction_c).c_str(),
                format_or_dash("%.2f", scan.junction_std_c).c_str(),
                format_or_dash("%.2f", scan.case_c).c_str(), scan.calibration_id,
                scan.beams.size());
  std::string text = line;
  if (range.first >= scan.beams.size()) return text;
  text += "   beam  angle_deg     raw_mm  compensated_mm  window_mm  window_std_mm  flags\n";
  for (std::size_t b = range.first; b < scan.beams.size() && b <= range.last; ++b) {
    const ipc::BeamValue& v = scan.beams[b];
    std::snprintf(line, sizeof line, "  %5zu  %9.2f  %9s  %14s  %9s  %13s  %s\n", b,
                  beam_angle_deg(scan, b), format_or_dash("%.1f", v.raw_mm).c_str(),
                  format_or_dash("%.2f", v.compensated_mm).c_str(),
                  format_or_dash("%.2f", v.window_mm).c_str(),
                  format_or_dash("%.3f", v.window_std_mm).c_str(),
                  joined(ipc::beam_flag_names(v.flags)).c_str());
    text += line;
  }
  return text;
}

nlohmann::json ring_json(const ring::RingReader& reader) {
  const ring::RingInfo info = reader.info();
  return {{"name", info.name},
          {"generation", info.generation},
          {"writer_pid", info.writer_pid},
          {"writer_running", reader.writer_running()},
          {"writer_closed", info.writer_closed},
          {"slot_count", info.slot_count},
          {"max_beams", info.max_beams},
          {"published", info.published}};
}

std::string ring_text(const ring::RingReader& reader) {
  const ring::RingInfo info = reader.info();
  char line[256];
  std::snprintf(
      line, sizeof line,
      "ring %s: writer pid %d (%s), generation %llu, %u slots of up to %u beams, "
      "%llu scans published\n",
      info.name.c_str(), info.writer_pid,
      reader.writer_running() ? "running" : (info.writer_closed ? "closed" : "not running"),
      static_cast<unsigned long long>(info.generation), info.slot_count, info.max_beams,
      static_cast<unsigned long long>(info.published));
  return line;
}

// The newest scans still in the ring: the latest one, or the `count` newest.
std::vector<ipc::CompensatedScan> newest_scans(ring::RingReader& reader, int count) {
  if (count <= 1) {
    auto latest = reader.latest();
    if (!latest) return {};
    return {std::move(*latest)};
  }
  reader.rewind_to_oldest();
  auto scans = reader.read_new().scans;
  if (scans.size() > static_cast<std::size_t>(count)) {
    scans.erase(scans.begin(), scans.end() - count);
  }
  return scans;
}

CommandResult dump_newest(ring::RingReader& reader, const ShmDumpOptions& o,
                          const BeamRange& range) {
  CommandResult result;
  result.json["ring"] = ring_json(reader);
  result.json["scans"] = nlohmann::json::array();
  result.text = ring_text(reader);
  const auto scans = newest_scans(reader, o.count);
  if (scans.empty()) result.text += "no scan published yet\n";
  for (const auto& scan : scans) {
    result.json["scans"].push_back(scan_json(scan, range));
    result.text += scan_text(scan, range);
  }
  return result;
}

// --follow: text goes out scan by scan; JSON is one document, printed when the command ends.
CommandResult follow(ring::RingReader& reader, const ShmDumpOptions& o, const BeamRange& range,
                     const CommonOptions& common) {
  const StopOnSignal stop;
  CommandResult result;
  result.json["ring"] = ring_json(reader);
  result.json["scans"] = nlohmann::json::array();
  if (!common.json) {
    std::fputs(ring_text(reader).c_str(), stdout);
    std::fflush(stdout);
  }
  const auto limit = o.count > 0 ? static_cast<std::uint64_t>(o.count) : ~std::uint64_t{0};
  std::uint64_t printed = 0;
  bool told_writer_gone = false;
  while (printed < limit && !stop.requested()) {
    const ring::ReadBatch batch = reader.read_new(static_cast<std::size_t>(limit - printed));
    if (batch.writer_restarted) {
      told_writer_gone = false;
      if (!common.quiet) {
        std::fprintf(stderr, "shm-dump: the writer re-created %s (generation %llu)\n",
                     o.name.c_str(), static_cast<unsigned long long>(reader.info().generation));
      }
    }
    if (batch.scans.empty() && !told_writer_gone && !reader.writer_running()) {
      told_writer_gone = true;
      if (!common.quiet) {
        std::fprintf(stderr,
                     "shm-dump: the writer of %s is not running; waiting for it to re-create "
                     "the ring\n",
                     o.name.c_str());
      }
    }
    if (batch.lost > 0 && !common.quiet) {
      std::fprintf(stderr, "shm-dump: %llu scans lost (overwritten before they were read)\n",
                   static_cast<unsigned long long>(batch.lost));
    }
    for (const auto& scan : batch.scans) {
      if (common.json) {
        result.json["scans"].push_back(scan_json(scan, range));
      } else {
        std::fputs(scan_text(scan, range).c_str(), stdout);
      }
      ++printed;
    }
    std::fflush(stdout);
    if (batch.scans.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  const ring::ReaderCounters& c = reader.counters();
  result.json["scans_read"] = c.scans_read;
  result.json["lost"] = c.lost;
  result.json["torn_reads"] = c.torn_reads;
  result.json["writer_restarts"] = c.writer_restarts;
  char text[200];
  std::snprintf(text, sizeof text,
                "%llu scans read, %llu lost, %llu torn reads discarded, %llu writer restarts\n",
                static_cast<unsigned long long>(c.scans_read),
                static_cast<unsigned long long>(c.lost),
                static_cast<unsigned long long>(c.torn_reads),
                static_cast<unsigned long long>(c.writer_restarts));
  result.text = text;
  return result;
}

CommandResult shm_dump(const ShmDumpOptions& o, const CommonOptions& common) {
  const BeamRange range = parse_beam_range(o.beams);
  ring::RingReader reader(o.name);
  return o.follow ? follow(reader, o, range, common) : dump_newest(reader, o, range);
}

}  // namespace

void register_shm_dump(CLI::App& app, const CommonOptions& common, CommandRunner& run) {
  auto* cmd = app.add_subcommand(
      "shm-dump",
      "Print the compensated scans tofcompd publishes to its shared-memory ring: the newest, "
      "or with --follow each new one");
  auto o = std::make_shared<ShmDumpOptions>();
  cmd->add_option("name", o->name, "Name of the ring's shm object")->capture_default_str();
  cmd->add_flag("-f,--follow", o->follow,
                "Print each new scan until SIGINT/SIGTERM or -n scans (with --json: one "
                "document at the end)");
  cmd->add_option("-n,--count", o->count,
                  "Scans to print: without --follow the newest N still in the ring")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--beams", o->beams, "Only beams FIRST:LAST (indices from 0, inclusive)")
      ->check(
          [](const std::string& text) {
            try {
              parse_beam_range(text);
              return std::string();
            } catch (const core::InvalidInput& e) {
              return std::string(e.what());
            }
          },
          "FIRST:LAST");
  cmd->callback([&common, &run, o] { run = [&common, o] { return shm_dump(*o, common); }; });
}

}  // namespace tofcomp::cli
