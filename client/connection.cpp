// Connection: the blocking socket client of ipc/socket behind the library's API. Connecting
// exchanges hello and refuses a daemon of another major protocol version; every failure of the
// layers below becomes an Error of the kind the C API returns.
#include <nlohmann/json.hpp>
#include <utility>

#include "client/public_scan.hpp"
#include "core/error.hpp"
#include "ipc/socket/client.hpp"
#include "ipc/socket/compact_frame.hpp"
#include "ipc/socket/protocol_constants.hpp"
#include "ipc/socket/protocol_error.hpp"
#include "ipc/socket/scan_json.hpp"
#include "tofcomp/client.hpp"

namespace tofcomp::client {

using client_detail::public_scan;

namespace {

namespace ipcs = ipc::socket;
using nlohmann::json;

// Runs f; what the socket client throws becomes an Error (Connect for a failure to connect).
template <typename F>
auto guarded(F&& f, ErrorKind otherwise = ErrorKind::BadData) {
  try {
    return f();
  } catch (const Error&) {
    throw;
  } catch (const ipcs::ProtocolError& e) {
    throw Error(ErrorKind::Daemon, e.what(), std::string(ipcs::to_string(e.code())));
  } catch (const ipcs::SocketClosed& e) {
    throw Error(ErrorKind::Closed, e.what());
  } catch (const ipcs::SocketTimeout& e) {
    throw Error(ErrorKind::Timeout, e.what());
  } catch (const core::Error& e) {
    throw Error(otherwise, e.what());
  } catch (const json::exception& e) {
    throw Error(ErrorKind::BadData, std::string("a reply that is not as the protocol says: ") +
                                        e.what());
  }
}

std::string version_text(int major, int minor) {
  return std::to_string(major) + "." + std::to_string(minor);
}

const std::string kThisLibrary = std::string("this library (libtofcomp-client ") +
                                 TOFCOMP_CLIENT_VERSION_STRING + ") speaks protocol " +
                                 version_text(TOFCOMP_PROTOCOL_VERSION_MAJOR,
                                              TOFCOMP_PROTOCOL_VERSION_MINOR);

Hello exchange_hello(ipcs::SocketClient& socket, std::chrono::milliseconds timeout) {
  const json reply = socket.request({{"op", "hello"}}, timeout);
  if (!reply.value("ok", false)) {
    const json error = reply.value("error", json::object());
    if (error.is_object() && error.value("code", "") == "unknown_op") {
      throw Error(ErrorKind::ProtocolVersion,
                  "tofcompd at " + socket.path() +
                      " does not know hello: it predates the versioned protocol (1.0); " +
                      kThisLibrary);
    }
    ipcs::check_reply(reply);
  }
  const json& stated = reply.at("hello");
  Hello hello{stated.at("protocol_major").get<int>(), stated.at("protocol_minor").get<int>(),
              stated.at("daemon").get<std::string>(),
              stated.at("daemon_version").get<std::string>()};
  if (hello.protocol_major != TOFCOMP_PROTOCOL_VERSION_MAJOR) {
    throw Error(ErrorKind::ProtocolVersion,
                hello.daemon + " " + hello.daemon_version + " at " + socket.path() +
                    " speaks protocol " + version_text(hello.protocol_major, hello.protocol_minor) +
                    "; " + kThisLibrary + ", and their major versions differ");
  }
  return hello;
}

json beams_json(const std::optional<BeamRange>& beams) {
  return json::array({beams->first, beams->last});
}

Scan scan_from_json(const json& object) {
  const ipcs::ReceivedScan received = ipcs::decode_scan(object);
  return public_scan(received.scan, received.span,
                     object.dump(-1, ' ', false, json::error_handler_t::replace));
}

}  // namespace

struct Connection::Impl {
  ipcs::SocketClient socket;
  Hello hello;
  Impl(const std::string& path, Duration timeout)
      : socket(guarded([&] { return ipcs::SocketClient(path, timeout); }, ErrorKind::Connect)),
        hello(guarded([&] { return exchange_hello(socket, timeout); })) {}
};

Connection::Connection(const std::string& path, Duration timeout)
    : impl_(std::make_unique<Impl>(path, timeout)) {}
Connection::~Connection() = default;
Connection::Connection(Connection&&) noexcept = default;
Connection& Connection::operator=(Connection&&) noexcept = default;

const Hello& Connection::hello() const {
  return impl_->hello;
}

const std::string& Connection::path() const {
  return impl_->socket.path();
}

Scan Connection::latest(std::optional<BeamRange> beams, Duration timeout) {
  return guarded([&] {
    json request{{"op", "latest"}};
    if (beams) request["beams"] = beams_json(beams);
    return scan_from_json(impl_->socket.call(request, timeout).at("scan"));
  });
}

void Connection::subscribe(std::optional<BeamRange> beams, std::uint32_t every, Format format,
                           Duration timeout) {
  guarded([&] {
    json request{{"op", "subscribe"},
                 {"every", every},
                 {"format", format == Format::Compact ? "compact" : "json"}};
    if (beams) request["beams"] = beams_json(beams);
    impl_->socket.call(request, timeout);
    return 0;
  });
}

std::optional<Scan> Connection::next_scan(Duration timeout) {
  return guarded([&]() -> std::optional<Scan> {
    auto message = impl_->socket.read_any(timeout);
    if (!message) return std::nullopt;
    if (message->is_frame()) {
      const auto received = ipcs::decode_compact_frame(message->frame);
      return public_scan(received.scan, received.span);
    }
    const json& line = message->json;
    if (line.is_object() && line.value("event", "") == "scan" && line.contains("scan")) {
      return scan_from_json(line["scan"]);
    }
    std::string text = line.dump(-1, ' ', false, json::error_handler_t::replace);
    constexpr std::size_t kQuoted = 200;
    if (text.size() > kQuoted) text = text.substr(0, kQuoted) + "...";
    throw Error(ErrorKind::BadData,
                "expected a scan from tofcompd at " + impl_->socket.path() + ", got " + text);
  });
}

void Connection::unsubscribe(Duration timeout) {
  guarded([&] {
    impl_->socket.call({{"op", "unsubscribe"}}, timeout);
    return 0;
  });
}

std::string Connection::call(const std::string& request_json, Duration timeout) {
  return guarded([&] {
    json request;
    try {
      request = json::parse(request_json);
    } catch (const json::exception& e) {
      throw Error(ErrorKind::InvalidArgument, std::string("request: not JSON: ") + e.what());
    }
    if (!request.is_object()) {
      throw Error(ErrorKind::InvalidArgument, "request: must be a JSON object");
    }
    const json reply = impl_->socket.request(std::move(request), timeout);
    ipcs::check_reply(reply);
    return reply.dump(-1, ' ', false, json::error_handler_t::replace);
  });
}

}  // namespace tofcomp::client
