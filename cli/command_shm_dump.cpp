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

#include "cli/beam_range_option.hpp"
#include "cli/command.hpp"
#include "cli/number_checks.hpp"
#include "cli/scan_text.hpp"
#include "cli/stream_output.hpp"
#include "core/error.hpp"
#include "ipc/default_places.hpp"
#include "ipc/instance_name.hpp"
#include "ipc/ring/ring_reader.hpp"
#include "ipc/socket/scan_json.hpp"
#include "ipc/user_name.hpp"

namespace tofcomp::cli {

namespace {

namespace ring = tofcomp::ipc::ring;

struct ShmDumpOptions {
  // Your own tofcompd's when it runs, the system's otherwise (ipc/default_places.hpp).
  std::string name = ipc::ring_to_read(ipc::current_user_environment());
  std::string instance;  // --instance: its ring replaces `name`
  bool follow = false;
  int count = 0;  // 0: the newest scan, or with --follow every scan until stopped
  std::string beams;
  std::vector<std::string> owners;  // users whose rings are read; empty: the reader's default
};

// --owner values, names or uids, as uids; core::InvalidInput for a user that does not exist.
std::vector<uid_t> owner_uids(const std::vector<std::string>& owners) {
  std::vector<uid_t> uids;
  for (const std::string& owner : owners) {
    if (const auto uid = ipc::user_named(owner)) {
      uids.push_back(*uid);
    } else if (!owner.empty() && owner.find_first_not_of("0123456789") == std::string::npos &&
               owner.size() < 10) {
      uids.push_back(static_cast<uid_t>(std::stoul(owner)));
    } else {
      throw core::InvalidInput("--owner: no user '" + owner + "'");
    }
  }
  return uids;
}

// How often --follow looks for new scans when the ring has none (the LMS 200 publishes every
// 13.3 ms at most).
constexpr std::chrono::milliseconds kFollowPoll{2};

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

// The beams of the wanted range the scan has (none beyond it).
ipc::socket::BeamSpan span_of(const ipc::CompensatedScan& scan,
                              const std::optional<ipc::socket::BeamRange>& wanted) {
  return ipc::socket::beams_clipped(wanted, scan.beams.size());
}

// The scan as the socket protocol's JSON object (ipc/socket/scan_json.hpp).
nlohmann::json scan_json(const ipc::CompensatedScan& scan,
                         const std::optional<ipc::socket::BeamRange>& wanted) {
  return nlohmann::json::parse(ipc::socket::encode_scan(scan, span_of(scan, wanted)));
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
                          const std::optional<ipc::socket::BeamRange>& range) {
  CommandResult result;
  result.json["ring"] = ring_json(reader);
  result.json["scans"] = nlohmann::json::array();
  result.text = ring_text(reader);
  const auto scans = newest_scans(reader, o.count);
  if (scans.empty()) result.text += "no scan published yet\n";
  for (const auto& scan : scans) {
    result.json["scans"].push_back(scan_json(scan, range));
    result.text += scan_text(scan, span_of(scan, range));
  }
  return result;
}

// --follow: each scan goes out as it is read, text or with --json one scan object per line (as
// `tofcomp query subscribe --json` streams them); at the end the summary, as text or as a last
// JSON line. A reader that goes away (`| head`) ends it with status 0, as SIGINT and SIGTERM do.
CommandResult follow(ring::RingReader& reader, const ShmDumpOptions& o,
                     const std::optional<ipc::socket::BeamRange>& range,
                     const CommonOptions& common) {
  const StopOnSignal stop;
  ::signal(SIGPIPE, SIG_IGN);  // a closed pipe is then EPIPE from the write
  CommandResult result;
  result.streamed = true;
  nlohmann::json summary;
  summary["ring"] = ring_json(reader);
  bool reader_gone = !common.json && !write_stream_line(ring_text(reader));
  const auto limit = o.count > 0 ? static_cast<std::uint64_t>(o.count) : ~std::uint64_t{0};
  std::uint64_t printed = 0;
  bool told_writer_gone = false;
  while (printed < limit && !stop.requested() && !reader_gone) {
    const ring::ReadBatch batch = reader.read_new(static_cast<std::size_t>(limit - printed));
    if (batch.writer_restarted) {
      told_writer_gone = false;
      if (!common.quiet) {
        std::fprintf(stderr, "shm-dump: the writer re-created %s (generation %llu)\n",
                     reader.name().c_str(),
                     static_cast<unsigned long long>(reader.info().generation));
      }
    }
    if (batch.scans.empty() && !told_writer_gone && !reader.writer_running()) {
      told_writer_gone = true;
      if (!common.quiet) {
        std::fprintf(stderr,
                     "shm-dump: the writer of %s is not running; waiting for it to re-create "
                     "the ring\n",
                     reader.name().c_str());
      }
    }
    if (batch.lost > 0 && !common.quiet) {
      std::fprintf(stderr, "shm-dump: %llu scans lost (overwritten before they were read)\n",
                   static_cast<unsigned long long>(batch.lost));
    }
    for (const auto& scan : batch.scans) {
      const std::string line = common.json ? nlohmann::json{{"scan", scan_json(scan, range)}}.dump()
                                           : scan_text(scan, span_of(scan, range));
      if (!write_stream_line(common.json ? line + "\n" : line)) {
        reader_gone = true;
        break;
      }
      ++printed;
    }
    if (batch.scans.empty()) std::this_thread::sleep_for(kFollowPoll);
  }
  if (reader_gone) return result;
  const ring::ReaderCounters& c = reader.counters();
  summary["scans_read"] = c.scans_read;
  summary["lost"] = c.lost;
  summary["torn_reads"] = c.torn_reads;
  summary["writer_restarts"] = c.writer_restarts;
  if (common.json) {
    write_stream_line(summary.dump() + "\n");
    return result;
  }
  char text[200];
  std::snprintf(text, sizeof text,
                "%llu scans read, %llu lost, %llu torn reads discarded, %llu writer restarts\n",
                static_cast<unsigned long long>(c.scans_read),
                static_cast<unsigned long long>(c.lost),
                static_cast<unsigned long long>(c.torn_reads),
                static_cast<unsigned long long>(c.writer_restarts));
  write_stream_line(text);
  return result;
}

CommandResult shm_dump(const ShmDumpOptions& o, const CommonOptions& common) {
  const std::optional<ipc::socket::BeamRange> range = parse_beam_range(o.beams);
  ring::RingReader reader(o.name, ring::RingReaderOptions{owner_uids(o.owners)});
  if (const auto foreign = reader.foreign_owner(); foreign && !common.quiet) {
    std::fprintf(stderr,
                 "shm-dump: %s belongs to %s, who is not tofcompd: not read; reading %s, where "
                 "tofcompd publishes when its name is taken\n",
                 o.name.c_str(), ipc::describe_user(*foreign).c_str(), reader.name().c_str());
  }
  return o.follow ? follow(reader, o, range, common) : dump_newest(reader, o, range);
}

}  // namespace

void register_shm_dump(CLI::App& app, const CommonOptions& common, CommandRunner& run) {
  auto* cmd = app.add_subcommand(
      "shm-dump",
      "Print the compensated scans tofcompd publishes to its shared-memory ring: the newest, "
      "or with --follow each new one");
  auto o = std::make_shared<ShmDumpOptions>();
  auto* name =
      cmd->add_option("name", o->name,
                      "Name of the ring's shm object; default: your own tofcompd's when it runs, "
                      "the system's otherwise")
          ->capture_default_str();
  cmd->add_option("-i,--instance", o->instance,
                  "The ring of tofcompd instance NAME (tofcompd@NAME.service): /tofcompd-NAME")
      ->check([](const std::string& instance) { return ipc::instance_name_problem(instance); },
              "NAME")
      ->excludes(name)
      ->each([o](const std::string& instance) { o->name = ipc::instance_ring_name(instance); });
  cmd->add_flag("-f,--follow", o->follow,
                "Print each new scan until SIGINT/SIGTERM or -n scans (with --json: one "
                "document at the end)");
  cmd->add_option("--owner", o->owners,
                  "A user whose rings are read (name or uid; repeatable). Default: you, root and "
                  "tofcompd; a ring of anyone else is refused")
      ->type_name("USER");
  cmd->add_option("-n,--count", o->count,
                  "Scans to print: without --follow the newest N still in the ring")
      ->check(at_least(1));
  add_beams_option(*cmd, o->beams);
  cmd->callback([&common, &run, o] { run = [&common, o] { return shm_dump(*o, common); }; });
}

}  // namespace tofcomp::cli
