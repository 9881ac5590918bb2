// tofcomp query: asks a running tofcompd over its Unix socket (docs/protocol.md) for the latest
// scan, its status or statistics, a reload or a recalibration, or the scans of a subscription
// (a number of them, or until interrupted); prints them as text (a table of beams) or, with
// --json, as the daemon sent them (a subscription's scans one JSON object per line). It talks to
// the daemon through libtofcomp-client (tofcomp/client.hpp), as any client program does: the
// connection states the protocol version (hello) and a daemon of another major one is refused.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "cli/beam_range_option.hpp"
#include "cli/command.hpp"
#include "cli/number_checks.hpp"
#include "cli/scan_text.hpp"
#include "cli/stream_output.hpp"
#include "core/error.hpp"
#include "ipc/default_places.hpp"
#include "ipc/instance_name.hpp"
#include "ipc/socket/protocol_constants.hpp"
#include "ipc/socket/scan_json.hpp"
#include "tofcomp/client.hpp"

namespace tofcomp::cli {

namespace {

namespace ipcs = tofcomp::ipc::socket;
using nlohmann::json;

// subscribe without -n: print scans until interrupted.
constexpr int kUntilStopped = 0;

struct QueryOptions {
  // Your own tofcompd's when it runs, the system's otherwise (ipc/default_places.hpp).
  std::string socket = ipc::socket_to_read(ipc::current_user_environment()).string();
  std::string instance;  // --instance: its socket replaces `socket`
  double timeout_s = 5.0;
  std::string beams;          // FIRST:LAST, or one index
  std::string args;           // recalibrate: a JSON object
  int count = kUntilStopped;  // subscribe: scans to print
  unsigned every = 1;
};

std::chrono::milliseconds timeout_of(const QueryOptions& o) {
  return std::chrono::milliseconds(static_cast<std::int64_t>(std::ceil(o.timeout_s * 1000.0)));
}

// The scan object of a reply as text (cli/scan_text.hpp).
std::string scan_text(const json& object) {
  const ipcs::ReceivedScan received = ipcs::decode_scan(object);
  return cli::scan_text(received.scan, received.span);
}

// A JSON object as "key: value" lines, nested objects as dotted keys.
void flatten(const json& value, const std::string& prefix, std::string& text) {
  if (value.is_object() && !value.empty()) {
    for (const auto& [key, member] : value.items()) {
      flatten(member, prefix.empty() ? key : prefix + "." + key, text);
    }
    return;
  }
  const std::string shown = value.is_string() ? value.get<std::string>() : value.dump();
  text += (prefix.empty() ? "" : prefix + ": ") + shown + "\n";
}

// Runs f against the daemon at socket; the library's errors become core::Error, a refusal
// naming the daemon's code.
template <typename F>
auto with_daemon(const std::string& socket, F&& f) {
  try {
    return f();
  } catch (const client::Error& e) {
    if (e.kind() == client::ErrorKind::Daemon) {
      throw core::Error("tofcompd at " + socket + " answered " + e.daemon_code() + ": " + e.what());
    }
    throw core::Error(e.what());
  }
}

std::optional<client::BeamRange> library_range(const std::string& beams) {
  const auto range = parse_beam_range(beams);
  if (!range) return std::nullopt;
  return client::BeamRange{range->first, range->last};
}

// The request for op, its options checked before anything is sent.
json request_for(const QueryOptions& o, const std::string& op) {
  json request{{"op", op}};
  if (op == "latest") {
    if (const auto beams = parse_beam_range(o.beams))
      request["beams"] = {beams->first, beams->last};
  }
  if (op == "recalibrate" && !o.args.empty()) {
    try {
      request["args"] = json::parse(o.args);
    } catch (const json::exception& e) {
      throw core::InvalidInput("--args: not JSON: " + std::string(e.what()));
    }
    if (!request["args"].is_object()) throw core::InvalidInput("--args: must be a JSON object");
  }
  return request;
}

CommandResult run_simple(const QueryOptions& o, const std::string& op) {
  const json request = request_for(o, op);
  const auto timeout = timeout_of(o);
  const json reply = with_daemon(o.socket, [&] {
    client::Connection daemon(o.socket, timeout);
    return json::parse(daemon.call(request.dump(), timeout));
  });
  CommandResult result;
  if (op == "latest") {
    result.json = reply.at("scan");
    result.text = scan_text(result.json);
  } else if (op == "status" || op == "stats") {
    result.json = reply;
    result.json.erase("id");
    result.json.erase("ok");
    flatten(result.json, "", result.text);
  } else {
    result.json = {{"message", reply.value("message", "")}};
    result.text = reply.value("message", "") + "\n";
  }
  return result;
}

CommandResult run_subscribe(const QueryOptions& o, const CommonOptions& common) {
  const auto beams = library_range(o.beams);
  const auto timeout = timeout_of(o);
  client::Connection daemon = with_daemon(o.socket, [&] {
    client::Connection connection(o.socket, timeout);
    connection.subscribe(beams, o.every, client::Format::Json, timeout);
    return connection;
  });
  const bool until_stopped = o.count == kUntilStopped;
  end_stream_on_interrupt();
  // Each scan is printed as it arrives: text, or with --json one scan object per line (the
  // object as the daemon sent it).
  for (int printed = 0; until_stopped || printed < o.count;) {
    auto scan = with_daemon(o.socket, [&] { return daemon.next_scan(timeout); });
    if (!scan) {
      if (until_stopped) continue;  // a quiet daemon: keep waiting, as gpspipe does
      throw core::Error("no scan from tofcompd at " + o.socket + " within " +
                        std::to_string(o.timeout_s) + " s after " + std::to_string(printed) +
                        " of " + std::to_string(o.count));
    }
    const std::string line =
        common.json ? scan->json + "\n" : scan_text(json::parse(scan->json)) + "\n";
    if (!write_stream_line(line)) break;  // the reader went away
    ++printed;
  }
  CommandResult result;
  result.streamed = true;
  return result;
}

}  // namespace

void register_query(CLI::App& app, const CommonOptions& common, CommandRunner& run) {
  auto* cmd =
      app.add_subcommand("query",
                         "Ask a running tofcompd over its socket: latest, status, stats, reload, "
                         "recalibrate, subscribe");
  auto o = std::make_shared<QueryOptions>();
  auto* socket = cmd->add_option("--socket", o->socket,
                                 "tofcompd's socket; default: your own tofcompd's when it runs, "
                                 "the system's otherwise")
                     ->capture_default_str()
                     ->type_name("PATH");
  cmd->add_option("-i,--instance", o->instance,
                  "The socket of tofcompd instance NAME (tofcompd@NAME.service): "
                  "/run/tofcompd/NAME/tofcompd.sock")
      ->check([](const std::string& name) { return ipc::instance_name_problem(name); }, "NAME")
      ->excludes(socket)
      ->each([o](const std::string& name) { o->socket = ipc::instance_socket_path(name); });
  cmd->add_option("--timeout", o->timeout_s, "Seconds to wait to connect and for each answer")
      ->check(greater_than(0))
      ->capture_default_str();
  cmd->require_subcommand(1);

  auto* latest = cmd->add_subcommand("latest", "The latest compensated scan");
  add_beams_option(*latest, o->beams);
  latest->callback([&run, o] { run = [o] { return run_simple(*o, "latest"); }; });

  for (const char* op : {"status", "stats", "reload"}) {
    const std::string name = op;
    auto* sub =
        cmd->add_subcommand(name, name == "status"  ? "The daemon's state"
                                  : name == "stats" ? "The daemon's counters and the socket's"
                                                    : "Re-read the configuration and calibration");
    sub->callback([&run, o, name] { run = [o, name] { return run_simple(*o, name); }; });
  }

  auto* recalibrate = cmd->add_subcommand("recalibrate", "Start a recalibration");
  recalibrate->add_option("--args", o->args, "Arguments for the daemon, a JSON object");
  recalibrate->callback([&run, o] { run = [o] { return run_simple(*o, "recalibrate"); }; });

  auto* subscribe = cmd->add_subcommand("subscribe", "Print scans as the daemon publishes them");
  subscribe
      ->add_option("-n,--count", o->count,
                   "Scans to print, then disconnect; without it, print scans until "
                   "interrupted (Ctrl-C) or the reader of the output goes away")
      ->check(at_least(1));
  subscribe->add_option("--every", o->every, "Only scans whose sequence is a multiple of this")
      ->check(between(1, ipcs::kMaxEvery))
      ->capture_default_str();
  add_beams_option(*subscribe, o->beams);
  subscribe->callback(
      [&run, &common, o] { run = [&common, o] { return run_subscribe(*o, common); }; });
}

}  // namespace tofcomp::cli
