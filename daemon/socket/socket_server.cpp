// The socket server: the listener, the connections, request lines to the dispatcher, published
// scans to the subscribers, and the bounded queues' accounting.
#include "daemon/socket/socket_server.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <map>
#include <optional>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "daemon/report_throttle.hpp"
#include "daemon/socket/client_connection.hpp"
#include "daemon/socket/request_dispatcher.hpp"
#include "daemon/socket/scan_fanout.hpp"
#include "daemon/socket/socket_path.hpp"
#include "ipc/socket/reply.hpp"

namespace tofcomp::daemon::socket {

namespace asio = boost::asio;
using asio::awaitable;
using asio::use_awaitable;
using Stream = asio::local::stream_protocol::socket;

namespace {
constexpr std::chrono::milliseconds kAcceptErrorPause{100};
// Connections turned away (max_clients) are logged at most this often.
constexpr std::chrono::seconds kRefusalWarningInterval{10};
// Connections beyond max_clients kept for the users who may control the daemon (ControlPolicy),
// so that readers holding every slot cannot keep the operator from reloading.
constexpr std::uint64_t kOperatorSlots = 1;
constexpr std::size_t kMaxPathBytes = sizeof(sockaddr_un::sun_path) - 1;

// Where start() binds before the socket is ready: a hidden name beside the path, so that the
// path appears only once the socket has its permissions and listens (a client connecting
// between bind and listen would be refused; one connecting before chmod would meet the umask's
// permissions). Empty when that name would not fit a Unix socket address: then the path itself.
std::string binding_name(const std::string& path) {
  const std::size_t slash = path.rfind('/');
  const std::string directory =
      slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
  const std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
  const std::string name = directory + "." + base + "." + std::to_string(::getpid());
  return name.size() <= kMaxPathBytes ? name : std::string();
}
}  // namespace

void SocketServerSettings::validate() const {
  const auto fail = [](const std::string& what) {
    throw core::InvalidInput("socket server: " + what);
  };
  if (path.empty()) fail("path: empty");
  if (path.size() > kMaxPathBytes) {
    fail("path: " + std::to_string(path.size()) + " bytes, more than the " +
         std::to_string(kMaxPathBytes) + " a Unix socket path may have");
  }
  if (permissions > 0777) fail("permissions: " + std::to_string(permissions) + " is above 0777");
  if (max_clients < 1) fail("max_clients: must be at least 1");
  if (max_request_bytes < ipc::socket::kSmallestMaxRequestBytes ||
      max_request_bytes > ipc::socket::kLargestMaxRequestBytes) {
    fail("max_request_bytes: " + std::to_string(max_request_bytes) + " is outside " +
         std::to_string(ipc::socket::kSmallestMaxRequestBytes) + ".." +
         std::to_string(ipc::socket::kLargestMaxRequestBytes));
  }
  if (max_queued_bytes_per_client < 1) fail("max_queued_bytes_per_client: must be at least 1");
  if (idle_timeout.count() <= 0) fail("idle_timeout: must be positive");
}

nlohmann::ordered_json to_json(const SocketServerCounters& c) {
  return {{"clients", c.clients},
          {"subscribers", c.subscribers},
          {"accepted_clients", c.accepted_clients},
          {"refused_clients", c.refused_clients},
          {"dropped_slow_clients", c.dropped_slow_clients},
          {"idle_clients_closed", c.idle_clients_closed},
          {"forbidden_requests", c.forbidden_requests},
          {"requests", c.requests},
          {"errors", c.errors},
          {"scans_published", c.scans_published},
          {"scan_encodings", c.scan_encodings},
          {"queued_bytes", c.queued_bytes},
          {"peak_queued_bytes", c.peak_queued_bytes},
          {"peak_client_queued_bytes", c.peak_client_queued_bytes}};
}

class SocketServer::Impl final : public ClientConnection::Owner,
                                 public std::enable_shared_from_this<Impl> {
 public:
  Impl(asio::io_context& io, SocketServerSettings settings, SocketRequestHandler& handler,
       SocketLog log)
      : settings_(std::move(settings)),
        io_(io),
        log_(std::move(log)),
        dispatcher_(handler, settings_.max_request_bytes, [this] { return to_json(counters()); }),
        control_(settings_.control_uids),
        acceptor_(io) {
    settings_.validate();
  }

  void start();
  void serve_activated_listener(int listener);
  // From here the acceptor's connections are taken; logs `message`.
  void begin_accepting(const std::string& message);
  void stop();
  void publish(const ipc::CompensatedScan& scan);
  SocketServerCounters counters() const;

  void on_line(ClientConnection& connection, std::string_view line) override;
  void on_overlong(ClientConnection& connection) override;
  void on_written(ClientConnection& connection, std::size_t bytes) override;
  void on_idle(ClientConnection& connection) override;
  void on_input_ended(ClientConnection& connection) override;
  void on_closed(ClientConnection& connection, const std::string& why,
                 std::size_t unwritten_bytes) override;

  SocketServerSettings settings_;
  bool running_ = false;

 private:
  // Which slot a connection holds: one of max_clients, the operator's, or none (turned away).
  enum class Slot { Regular, Operator, None };
  struct Client {
    std::shared_ptr<ClientConnection> connection;
    Slot slot = Slot::None;
    std::optional<Subscription> subscription;
  };

  asio::io_context& io_;
  SocketLog log_;
  RequestDispatcher dispatcher_;
  ControlPolicy control_;
  asio::local::stream_protocol::acceptor acceptor_;
  std::map<std::uint64_t, Client> clients_;
  std::uint64_t next_number_ = 1;
  std::uint64_t admitted_now_ = 0;   // connections in the max_clients slots
  std::uint64_t operators_now_ = 0;  // connections in the operator's slots beyond them
  std::uint64_t generation_ = 0;     // of the accept loop: a restarted server ignores the old one
  SocketServerCounters counters_;
  std::optional<FileIdentity> made_;
  ReportThrottle refusal_warnings_{kRefusalWarningInterval};

  awaitable<void> accept_loop(std::shared_ptr<Impl> self, std::uint64_t generation);
  void admit(Stream stream);
  // A reply is always queued (requests wait while the queue is over half its bound, so replies
  // cannot overflow it); a scan that would pass the bound drops the connection.
  enum class Line { Reply, Scan };
  void enqueue(ClientConnection& connection, std::shared_ptr<const std::string> line, Line kind);
  void log(SocketLogLevel level, const std::string& message) const {
    if (log_) log_(level, "socket: " + message);
  }
  std::string name(const ClientConnection& c) const {
    return "client " + std::to_string(c.number());
  }
  static std::string peer_name(const ClientConnection& c) {
    return c.peer() ? describe_user(c.peer()->uid) + ", pid " + std::to_string(c.peer()->pid)
                    : std::string("a peer without credentials");
  }
};

void SocketServer::Impl::start() {
  if (running_) return;
  if (settings_.activated_listener) {
    serve_activated_listener(*settings_.activated_listener);
    return;
  }
  const std::string& path = settings_.path;
  if (clear_stale_socket(path)) log(SocketLogLevel::Info, "removed the stale socket file " + path);
  const std::string hidden = binding_name(path);
  const std::string& bound = hidden.empty() ? path : hidden;
  // A file left at the hidden name by this process id is a socket of a daemon that died.
  if (!hidden.empty()) clear_stale_socket(hidden);
  boost::system::error_code ec;
  acceptor_.open(asio::local::stream_protocol(), ec);
  if (!ec) acceptor_.bind(asio::local::stream_protocol::endpoint(bound), ec);
  if (ec) {
    boost::system::error_code ignored;
    acceptor_.close(ignored);
    throw core::Error("cannot bind the socket " + path + ": " + ec.message() +
                      (ec == boost::system::errc::no_such_file_or_directory
                           ? " (its directory does not exist)"
                           : ""));
  }
  made_ = identity_of(bound);
  const auto undo = [&](const std::string& what) {
    boost::system::error_code ignored;
    acceptor_.close(ignored);
    if (made_) {
      remove_if_same(bound, *made_);
      remove_if_same(path, *made_);
    }
    made_.reset();
    throw core::Error(what);
  };
  if (::chmod(bound.c_str(), static_cast<mode_t>(settings_.permissions)) != 0) {
    undo("cannot set the permissions of " + path + ": " + std::strerror(errno));
  }
  acceptor_.listen(asio::socket_base::max_listen_connections, ec);
  if (ec) undo("cannot listen on " + path + ": " + ec.message());
  // The listening socket's file gets the path as a second name (link fails, where rename would
  // replace, when another daemon claimed the path meanwhile), then loses the hidden one: from
  // here a client that finds the path connects.
  if (!hidden.empty()) {
    if (::link(hidden.c_str(), path.c_str()) != 0) {
      const int error = errno;
      undo(error == EEXIST ? "another process claimed " + path + " while tofcompd started"
                           : "cannot name the socket " + path + ": " + std::strerror(error));
    }
    ::unlink(hidden.c_str());
  }
  begin_accepting("listening on " + path);
}

void SocketServer::Impl::serve_activated_listener(int listener) {
  // A duplicate: stop() closes the acceptor's descriptor, and a later start() serves again.
  const int fd = ::fcntl(listener, F_DUPFD_CLOEXEC, 0);
  if (fd < 0) {
    throw core::Error("cannot serve the socket the service manager passed for " + settings_.path +
                      ": " + std::strerror(errno));
  }
  boost::system::error_code ec;
  acceptor_.assign(asio::local::stream_protocol(), fd, ec);
  if (ec) {
    ::close(fd);
    throw core::Error("cannot serve the socket the service manager passed for " + settings_.path +
                      ": " + ec.message());
  }
  begin_accepting("listening on " + settings_.path + ", the socket the service manager passed");
}

void SocketServer::Impl::begin_accepting(const std::string& message) {
  running_ = true;
  asio::co_spawn(io_, accept_loop(shared_from_this(), ++generation_), asio::detached);
  log(SocketLogLevel::Info, message);
}

void SocketServer::Impl::stop() {
  if (!running_) return;
  running_ = false;
  boost::system::error_code ignored;
  acceptor_.close(ignored);
  auto clients = std::move(clients_);
  clients_.clear();
  for (auto& [number, client] : clients) client.connection->close("the server stopped", false);
  admitted_now_ = 0;
  operators_now_ = 0;
  counters_.queued_bytes = 0;
  if (made_) remove_if_same(settings_.path, *made_);
  made_.reset();
  log(SocketLogLevel::Info, "stopped listening on " + settings_.path);
}

awaitable<void> SocketServer::Impl::accept_loop(std::shared_ptr<Impl> /*keeps this alive*/,
                                                std::uint64_t generation) {
  for (;;) {
    boost::system::error_code ec;
    Stream stream = co_await acceptor_.async_accept(asio::redirect_error(use_awaitable, ec));
    if (!running_ || generation != generation_) co_return;
    if (ec) {
      // Out of descriptors, most likely: wait a little rather than spin.
      log(SocketLogLevel::Warning, "accepting a connection failed: " + ec.message());
      asio::steady_timer pause(io_, kAcceptErrorPause);
      co_await pause.async_wait(asio::redirect_error(use_awaitable, ec));
      if (!running_ || generation != generation_) co_return;
      continue;
    }
    admit(std::move(stream));
  }
}

void SocketServer::Impl::admit(Stream stream) {
  const std::uint64_t number = next_number_++;
  const ClientConnection::Limits limits{settings_.max_request_bytes,
                                        settings_.max_queued_bytes_per_client / 2,
                                        settings_.idle_timeout};
  auto connection = std::make_shared<ClientConnection>(std::move(stream), number, limits, *this);
  // Readers cannot lock out the operator: a user who may control the daemon finds a slot of
  // its own when max_clients are taken.
  Slot slot = Slot::None;
  if (admitted_now_ < settings_.max_clients) {
    slot = Slot::Regular;
    ++admitted_now_;
  } else if (operators_now_ < kOperatorSlots && control_.may_control(connection->peer())) {
    slot = Slot::Operator;
    ++operators_now_;
  }
  clients_.emplace(number, Client{connection, slot, std::nullopt});
  connection->start();
  if (slot != Slot::None) {
    ++counters_.accepted_clients;
    return;
  }
  ++counters_.refused_clients;
  // A flood of connections must not flood the log: one warning per interval, and the count of
  // those turned away unlogged meanwhile.
  if (const auto passed_over = refusal_warnings_.report(std::chrono::steady_clock::now())) {
    log(SocketLogLevel::Warning,
        name(*connection) + " turned away: " + std::to_string(settings_.max_clients) +
            " clients are connected (max_clients)" +
            (*passed_over > 0
                 ? "; " + std::to_string(*passed_over) + " more turned away since the last warning"
                 : std::string()));
  }
  enqueue(*connection,
          std::make_shared<const std::string>(ipc::socket::encode_error_reply(
              std::nullopt, ipc::socket::ErrorCode::Unavailable,
              "connection: too many clients; " + std::to_string(settings_.max_clients) +
                  " are connected, the most the daemon serves (max_clients)")),
          Line::Reply);
  connection->close_after_flush();
}

void SocketServer::Impl::enqueue(ClientConnection& connection,
                                 std::shared_ptr<const std::string> line, Line kind) {
  if (!connection.accepting()) return;
  const std::size_t bound = settings_.max_queued_bytes_per_client;
  if (kind == Line::Scan && !connection.fits(line->size(), bound)) {
    ++counters_.dropped_slow_clients;
    const std::string why =
        "dropped: it is not reading (" + std::to_string(connection.queued_bytes()) +
        " bytes queued, a line of " + std::to_string(line->size()) +
        " more would pass max_queued_bytes_per_client " + std::to_string(bound) + ")";
    log(SocketLogLevel::Warning, name(connection) + " " + why);
    connection.close(why);
    return;
  }
  const std::size_t bytes = line->size();
  connection.push(std::move(line));
  counters_.queued_bytes += bytes;
  counters_.peak_queued_bytes = std::max(counters_.peak_queued_bytes, counters_.queued_bytes);
  counters_.peak_client_queued_bytes =
      std::max<std::uint64_t>(counters_.peak_client_queued_bytes, connection.queued_bytes());
}

void SocketServer::Impl::publish(const ipc::CompensatedScan& scan) {
  if (!running_) return;
  ++counters_.scans_published;
  ScanFanout fanout(scan);
  // The lines first, then the queueing: a drop while queueing changes clients_.
  std::vector<std::pair<std::shared_ptr<ClientConnection>, std::shared_ptr<const std::string>>>
      sends;
  for (const auto& [number, client] : clients_) {
    if (!client.subscription || !client.connection->accepting()) continue;
    if (auto line = fanout.line_for(*client.subscription)) {
      sends.emplace_back(client.connection, std::move(line));
    }
  }
  counters_.scan_encodings += fanout.encodings();
  for (auto& [connection, line] : sends) enqueue(*connection, std::move(line), Line::Scan);
}

SocketServerCounters SocketServer::Impl::counters() const {
  SocketServerCounters c = counters_;
  c.clients = admitted_now_ + operators_now_;
  c.subscribers = 0;
  for (const auto& [number, client] : clients_) {
    if (client.slot != Slot::None && client.subscription && client.connection->accepting()) {
      ++c.subscribers;
    }
  }
  return c;
}

void SocketServer::Impl::on_line(ClientConnection& connection, std::string_view line) {
  const auto it = clients_.find(connection.number());
  if (it == clients_.end()) return;
  ++counters_.requests;
  const Caller caller{control_.may_control(connection.peer()), peer_name(connection),
                      control_.describe()};
  Answer answer = dispatcher_.answer(line, it->second.subscription, caller);
  if (answer.error) ++counters_.errors;
  if (answer.forbidden) {
    ++counters_.forbidden_requests;
    log(SocketLogLevel::Warning, name(connection) + " (" + caller.peer +
                                     "): " + "control request refused: not allowed to control");
  }
  enqueue(connection, std::make_shared<const std::string>(std::move(answer.line)), Line::Reply);
  if (answer.close) {
    log(SocketLogLevel::Info, name(connection) + ": request too long; closing its connection");
    connection.close_after_flush();
  }
}

void SocketServer::Impl::on_overlong(ClientConnection& connection) {
  ++counters_.requests;
  ++counters_.errors;
  enqueue(connection,
          std::make_shared<const std::string>(ipc::socket::encode_error_reply(
              std::nullopt, ipc::socket::ErrorCode::TooLong,
              "request: more than " + std::to_string(settings_.max_request_bytes) +
                  " bytes without a line end (the limit of a request)")),
          Line::Reply);
  log(SocketLogLevel::Info, name(connection) + ": request too long; closing its connection");
  connection.close_after_flush();
}

// A connection that sent no request and was delivered nothing for the idle timeout is told why
// and closed, so that silent clients cannot hold every slot: a subscriber that is sent scans is
// in use; one whose `every` or beams bring it nothing is not.
void SocketServer::Impl::on_idle(ClientConnection& connection) {
  const auto it = clients_.find(connection.number());
  if (it == clients_.end()) return;
  ++counters_.idle_clients_closed;
  const std::int64_t ms = settings_.idle_timeout.count();
  const std::string span =
      ms % 1000 == 0 ? std::to_string(ms / 1000) + " s" : std::to_string(ms) + " ms";
  enqueue(connection,
          std::make_shared<const std::string>(ipc::socket::encode_error_reply(
              std::nullopt, ipc::socket::ErrorCode::Unavailable,
              "connection: no request and nothing delivered for " + span +
                  " (idle_timeout_s); closing it to free its slot")),
          Line::Reply);
  log(SocketLogLevel::Info, name(connection) + ": idle for " + span + "; closing its connection");
  connection.close_after_flush();
}

// A client that shut its side after its requests has them answered; then it is closed after
// the replies, unless it subscribed: a subscriber half-closed (`nc -N`) still wants the scans,
// and a write tells when it has gone.
void SocketServer::Impl::on_input_ended(ClientConnection& connection) {
  const auto it = clients_.find(connection.number());
  if (it == clients_.end()) return;
  if (it->second.subscription) {
    log(SocketLogLevel::Info, name(connection) + " shut its side; its subscription goes on");
    return;
  }
  connection.close_after_flush();
}

void SocketServer::Impl::on_written(ClientConnection&, std::size_t bytes) {
  counters_.queued_bytes -= std::min<std::uint64_t>(bytes, counters_.queued_bytes);
}

void SocketServer::Impl::on_closed(ClientConnection& connection, const std::string& why,
                                   std::size_t unwritten_bytes) {
  counters_.queued_bytes -= std::min<std::uint64_t>(unwritten_bytes, counters_.queued_bytes);
  const auto it = clients_.find(connection.number());
  if (it == clients_.end()) return;
  if (it->second.slot == Slot::Regular) --admitted_now_;
  if (it->second.slot == Slot::Operator) --operators_now_;
  clients_.erase(it);
  log(SocketLogLevel::Info, name(connection) + " closed: " + why);
}

SocketServer::SocketServer(asio::io_context& io, SocketServerSettings settings,
                           SocketRequestHandler& handler, SocketLog log)
    : impl_(std::make_shared<Impl>(io, std::move(settings), handler, std::move(log))) {}

SocketServer::~SocketServer() {
  stop();
}

void SocketServer::start() {
  impl_->start();
}
void SocketServer::stop() {
  impl_->stop();
}
void SocketServer::publish(const ipc::CompensatedScan& scan) {
  impl_->publish(scan);
}
SocketServerCounters SocketServer::counters() const {
  return impl_->counters();
}
const SocketServerSettings& SocketServer::settings() const {
  return impl_->settings_;
}
bool SocketServer::running() const {
  return impl_->running_;
}

}  // namespace tofcomp::daemon::socket
