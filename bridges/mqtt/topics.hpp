// The bridge's topics: PREFIX/SITE/INSTANCE/NAME (docs/integration.md, "Topics"), one tree per
// scanner, so that a fleet subscribes to PREFIX/SITE/+/status or PREFIX/+/+/online.
#pragma once

#include <string>

#include "bridges/mqtt/bridge_config.hpp"

namespace tofcomp::bridges::mqtt {

struct Topics {
  explicit Topics(const BridgeConfig& config)
      : base(config.topic_prefix + "/" + config.site + "/" + config.instance) {}

  std::string base;
  std::string online() const { return base + "/online"; }
  std::string status() const { return base + "/status"; }
  std::string calibration() const { return base + "/calibration"; }
  std::string junction() const { return base + "/junction"; }
  std::string diagnosis() const { return base + "/diagnosis"; }
  std::string ranges() const { return base + "/ranges"; }
  std::string command() const { return base + "/command"; }
  std::string reply() const { return base + "/reply"; }
};

// The payloads of the online topic (retained; "offline" is also the last will).
inline constexpr const char* kOnline = "online";
inline constexpr const char* kOffline = "offline";

}  // namespace tofcomp::bridges::mqtt
