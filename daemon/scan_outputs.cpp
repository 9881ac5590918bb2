#include "daemon/scan_outputs.hpp"

#include <spdlog/spdlog.h>

#include <filesystem>
#include <system_error>
#include <utility>

namespace tofcomp::daemon {

ScanOutputs::ScanOutputs(boost::asio::io_context& io, const settings::OutputsConfig& config,
                         socket::SocketRequestHandler& requests, ServiceStatus& service)
    : service_(service), socket_path_(config.socket.path.string()) {
  const auto& shm = config.shm;
  ring_ = std::make_unique<ipc::ring::RingWriter>(shm.name, static_cast<std::uint32_t>(shm.slots),
                                                  ipc::ring::kDefaultMaxBeams,
                                                  ipc::ring::RingWriterOptions{shm.mode, false});
  const auto& so = config.socket;
  if (so.path.has_parent_path()) {
    std::error_code ignored;  // a failure shows when the server binds, naming the path
    std::filesystem::create_directories(so.path.parent_path(), ignored);
  }
  socket::SocketServerSettings settings;
  settings.path = socket_path_;
  settings.permissions = so.mode;
  settings.max_clients = static_cast<std::size_t>(so.max_clients);
  settings.max_request_bytes = so.max_request_bytes;
  settings.max_queued_bytes_per_client = so.max_queued_bytes_per_client;
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
