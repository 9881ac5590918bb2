// The command topic's messages: untrusted, so each is read as a request of tofcompd's own socket
// protocol (ipc/socket/request.hpp: strict JSON, bounded size and depth, no key twice, only known
// ops and fields), and only the control ops this bridge's configuration allows (commands.reload,
// commands.recalibrate, both off by default) are passed on. Every message gets a reply on the
// reply topic, in the protocol's reply form, with the command's id.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

#include "bridges/mqtt/bridge_config.hpp"

namespace tofcomp::bridges::mqtt {

// The largest command accepted: no command needs more than a few hundred bytes.
inline constexpr std::size_t kMaxCommandBytes = 1024;

// What to do with one command message: pass `request` (the op and its args, without the id) to
// tofcompd and answer with its reply under `id`, or answer with `refusal` at once.
struct CommandDecision {
  std::optional<nlohmann::json> id;
  std::optional<nlohmann::json> request;
  std::string refusal;  // the reply line when request is absent
};

// `config_source` names the configuration in refusals ("reload: not allowed by this bridge:
// commands.reload is false in /etc/tofcomp-mqtt-bridge/left.yaml").
CommandDecision decide_command(std::string_view payload, const CommandPermissions& permissions,
                               const std::string& config_source);

// The reply to a passed command: tofcompd's reply line (ok) with its id replaced by the
// command's.
std::string relay_reply(const std::optional<nlohmann::json>& id, const std::string& daemon_reply);

}  // namespace tofcomp::bridges::mqtt
