#include "daemon/scan_outputs.hpp"

#include <spdlog/spdlog.h>

#include <filesystem>
#include <system_error>
#include <utility>

#include "ipc/user_name.hpp"

namespace tofcomp::daemon {

ScanOutputs::ScanOutputs(boost::asio::io_context& io, const settings::OutputsConfig& config,
                         socket::SocketRequestHandler& requests, ServiceStatus& service)
    : service_(service),
      activated_(service::take_activated_socket()),
      socket_path_(activated_ ? activated_->path : config.socket.path.string()),
      lock_(std::filesystem::absolute(socket_path_)) {
  if (activated_ && std::filesystem::path(activated_->path) != config.socket.path) {
    spdlog::warn(
        "the service manager passed a socket at {}: served there, not at outputs.socket.path {}; "
        "clients that read the configuration look there (make ListenStream= and the path one)",
        activated_->path, config.socket.path.string());
  }
  const auto& shm = config.shm;
  ring_ = std::make_unique<ipc::ring::RingWriter>(
      shm.name, static_cast<std::uint32_t>(shm.slots), ipc::ring::kDefaultMaxBeams,
      ipc::ring::RingWriterOptions{shm.mode, false, true});
  if (const auto owner = ring_->foreign_owner()) {
    spdlog::warn(
        "shm object '{}' belongs to {}, not to this daemon's user: another user made it, and it is "
        "left alone; publishing to '{}' instead, where readers look (docs/shm-ring.md)",
        shm.name, ipc::describe_user(*owner), ring_->name());
  }
  const auto& so = config.socket;
  socket::SocketServerSettings settings;
  settings.path = socket_path_;
  settings.permissions = so.mode;
  settings.max_clients = static_cast<std::size_t>(so.max_clients);
  settings.max_request_bytes = so.max_request_bytes;
  settings.max_queued_bytes_per_client = so.max_queued_bytes_per_client;
  settings.idle_timeout = so.idle_timeout;
  if (activated_) settings.activated_listener = activated_->fd;
  server_ = std::make_unique<socket::SocketServer>(
      io, settings, requests, [](socket::SocketLogLevel level, const std::string& message) {
        if (level == socket::SocketLogLevel::Warning) {
          spdlog::warn("{}", message);
        } else {
          spdlog::info("{}", message);
        }
      });
  server_->start();
}

void ScanOutputs::publish(ipc::CompensatedScan scan) {
  ring_->publish(scan);
  server_->publish(scan);
  latest_ = std::move(scan);
  ++scans_published_;
  service_.scan_published();
}

void ScanOutputs::stop() {
  server_->stop();
}

}  // namespace tofcomp::daemon
