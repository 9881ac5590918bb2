// Where the compensated scans go: the shared-memory ring (ipc/ring/) and the Unix socket's
// subscribers (daemon/socket/), and the latest one for the socket's `latest` request; the first
// published makes the service ready. Takes the runtime directory's lock first (one daemon per
// runtime directory: daemon/instance_lock.hpp). A ring name taken by another user's object is
// left alone: the ring goes to its alternative name, and the log says so. A listening socket the
// service manager passed (socket activation: tofcompd.socket) is served in place of
// outputs.socket.path, and the log says where it is. Owns the lock, the ring writer, the socket
// server, the latest scan and the count of scans published.
#pragma once

#include <boost/asio/io_context.hpp>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "daemon/instance_lock.hpp"
#include "daemon/service/socket_activation.hpp"
#include "daemon/service_status.hpp"
#include "daemon/socket/request_handler.hpp"
#include "daemon/socket/socket_server.hpp"
#include "ipc/compensated_scan.hpp"
#include "ipc/ring/ring_writer.hpp"
#include "settings/daemon_config.hpp"

namespace tofcomp::daemon {

class ScanOutputs {
 public:
  // Creates the ring and starts the socket server, whose requests `requests` answers (on the
  // loop). Throws core::Error naming the ring or socket.
  ScanOutputs(boost::asio::io_context& io, const settings::OutputsConfig& config,
              socket::SocketRequestHandler& requests, ServiceStatus& service);

  void publish(ipc::CompensatedScan scan);
  void stop();

  // The latest scan published; nullptr before the first.
  const ipc::CompensatedScan* latest() const { return latest_ ? &*latest_ : nullptr; }
  std::uint64_t scans_published() const { return scans_published_; }
  const ipc::ring::RingWriter& ring() const { return *ring_; }
  const std::string& socket_path() const { return socket_path_; }

 private:
  ServiceStatus& service_;
  std::optional<service::ActivatedSocket> activated_;  // taken before the path and the lock
  std::string socket_path_;
  InstanceLock lock_;
  std::unique_ptr<ipc::ring::RingWriter> ring_;
  std::unique_ptr<socket::SocketServer> server_;
  std::optional<ipc::CompensatedScan> latest_;
  std::uint64_t scans_published_ = 0;  // to the ring and the socket
};

}  // namespace tofcomp::daemon
