// The request dispatcher: one parsed request to one reply line.
#include "daemon/socket/request_dispatcher.hpp"

#include <exception>
#include <utility>

#include "core/error.hpp"
#include "io/version.hpp"
#include "ipc/socket/reply.hpp"
#include "ipc/socket/scan_json.hpp"

namespace tofcomp::daemon::socket {

namespace ipcs = ipc::socket;
using nlohmann::ordered_json;

namespace {

ordered_json subscription_json(const Subscription& s) {
  ordered_json beams = nullptr;
  if (s.beams) beams = ordered_json::array({s.beams->first, s.beams->last});
  return ordered_json{{"beams", beams}, {"every", s.every}, {"format", ipcs::to_string(s.format)}};
}

}  // namespace

RequestDispatcher::RequestDispatcher(SocketRequestHandler& handler, std::size_t max_request_bytes,
                                     CountersJson socket_counters)
    : handler_(handler),
      max_request_bytes_(max_request_bytes),
      socket_counters_(std::move(socket_counters)) {}

Answer RequestDispatcher::answer(std::string_view line, std::optional<Subscription>& subscription,
                                 const Caller& caller) {
  std::optional<nlohmann::json> id;
  const auto error = [&](ipcs::ErrorCode code, const std::string& message) {
    return Answer{ipcs::encode_error_reply(id, code, message), true,
                  code == ipcs::ErrorCode::TooLong, code == ipcs::ErrorCode::Forbidden};
  };
  try {
    const ipcs::Request request = ipcs::parse_request(line, max_request_bytes_);
    id = request.id;
    const bool control = request.op == ipcs::Op::Reload || request.op == ipcs::Op::Recalibrate;
    if (control && !caller.may_control) {
      return error(ipcs::ErrorCode::Forbidden,
                   std::string(ipcs::to_string(request.op)) + ": not allowed for " + caller.peer +
                       "; control requests (reload, recalibrate) are for " + caller.controllers +
                       " only, reading requests (latest, subscribe, status, stats) for anyone "
                       "who may connect (docs/protocol.md)");
    }
    return Answer{execute(request, subscription)};
  } catch (const ipcs::ProtocolError& e) {
    if (e.id()) id = e.id();
    return error(e.code(), e.what());
  } catch (const core::InvalidInput& e) {
    return error(ipcs::ErrorCode::BadRequest, e.what());
  } catch (const std::exception& e) {
    return error(ipcs::ErrorCode::Internal, std::string("internal error: ") + e.what());
  } catch (...) {
    return error(ipcs::ErrorCode::Internal, "internal error: an unknown exception");
  }
}

std::string RequestDispatcher::execute(const ipcs::Request& request,
                                       std::optional<Subscription>& subscription) {
  using ipcs::Op;
  switch (request.op) {
    case Op::Latest: {
      const ipc::CompensatedScan* scan = handler_.latest_scan();
      if (scan == nullptr) {
        throw ipcs::ProtocolError(ipcs::ErrorCode::Unavailable,
                                  "latest: no scan has been published yet");
      }
      const ipcs::BeamSpan span = ipcs::beams_exactly(request.beams, scan->beams.size());
      return ipcs::encode_scan_reply(request.id, ipcs::encode_scan(*scan, span));
    }
    case Op::Subscribe: {
      // Against the scan at hand a range is checked now; later scans are clipped to it.
      if (request.beams) {
        if (const ipc::CompensatedScan* scan = handler_.latest_scan()) {
          ipcs::beams_exactly(request.beams, scan->beams.size());
        }
      }
      subscription = Subscription{request.beams, request.every, request.format};
      return ipcs::encode_ok_reply(
          request.id, ordered_json{{"subscription", subscription_json(*subscription)}});
    }
    case Op::Unsubscribe:
      subscription.reset();
      return ipcs::encode_ok_reply(request.id, ordered_json{{"subscription", nullptr}});
    case Op::Hello:
      return ipcs::encode_ok_reply(
          request.id, ordered_json{{"hello",
                                    {{"protocol_major", ipcs::kProtocolVersionMajor},
                                     {"protocol_minor", ipcs::kProtocolVersionMinor},
                                     {"daemon", "tofcompd"},
                                     {"daemon_version", io::kVersion}}}});
    case Op::Status:
      return ipcs::encode_ok_reply(request.id, ordered_json{{"status", handler_.status()}});
    case Op::Stats:
      return ipcs::encode_ok_reply(
          request.id, ordered_json{{"stats", handler_.stats()}, {"socket", socket_counters_()}});
    case Op::Reload: {
      const ReloadResult result = handler_.reload();
      if (!result.ok)
        throw ipcs::ProtocolError(ipcs::ErrorCode::Refused, "reload: " + result.message);
      return ipcs::encode_ok_reply(request.id, ordered_json{{"message", result.message}});
    }
    case Op::Recalibrate: {
      const RecalibrationResult result = handler_.recalibrate(request.args);
      if (!result.accepted) {
        throw ipcs::ProtocolError(ipcs::ErrorCode::Refused, "recalibrate: " + result.message);
      }
      return ipcs::encode_ok_reply(request.id, ordered_json{{"message", result.message}});
    }
  }
  throw ipcs::ProtocolError(ipcs::ErrorCode::Internal, "op: not handled by the server");
}

}  // namespace tofcomp::daemon::socket
