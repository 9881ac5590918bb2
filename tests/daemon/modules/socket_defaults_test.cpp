// The socket server's defaults are the configuration's (issue 15: the server carried 64 clients
// and 8 MiB per client where tofcompd.yaml, its reference and the docs said 16 and 1 MiB): a
// server made without settings behaves as the daemon's default configuration says.
#include <gtest/gtest.h>

#include "daemon/socket/socket_server.hpp"
#include "settings/daemon_config.hpp"
#include "settings/embedded_default_config.hpp"

namespace tofcomp::daemon {
namespace {

TEST(SocketDefaults, TheServersAreTheConfigurations) {
  const socket::SocketServerSettings server;
  const settings::SocketOutputConfig config;
  EXPECT_EQ(server.path, config.path.string());
  EXPECT_EQ(server.permissions, config.mode);
  EXPECT_EQ(server.max_clients, static_cast<std::size_t>(config.max_clients));
  EXPECT_EQ(server.max_request_bytes, config.max_request_bytes);
  EXPECT_EQ(server.max_queued_bytes_per_client, config.max_queued_bytes_per_client);
  EXPECT_EQ(server.idle_timeout, config.idle_timeout);
}

TEST(SocketDefaults, TheShippedConfigurationSaysTheSame) {
  // config/tofcompd.yaml spells every key out; its values are the defaults the docs give.
  const settings::SocketOutputConfig shipped = settings::embedded_default_config().outputs.socket;
  const socket::SocketServerSettings server;
  EXPECT_EQ(server.max_clients, 16u);
  EXPECT_EQ(server.max_queued_bytes_per_client, 1u << 20);
  EXPECT_EQ(server.max_clients, static_cast<std::size_t>(shipped.max_clients));
  EXPECT_EQ(server.max_request_bytes, shipped.max_request_bytes);
  EXPECT_EQ(server.max_queued_bytes_per_client, shipped.max_queued_bytes_per_client);
  EXPECT_EQ(server.idle_timeout, shipped.idle_timeout);
  EXPECT_EQ(server.permissions, shipped.mode);
}

}  // namespace
}  // namespace tofcomp::daemon
