// Deciding a command of the command topic.
#include "bridges/mqtt/remote_command.hpp"

#include "ipc/socket/reply.hpp"
#include "ipc/socket/request.hpp"

namespace tofcomp::bridges::mqtt {

namespace ipcs = ipc::socket;

namespace {

// A reply line of the protocol as an MQTT payload: without its line end.
std::string payload_of(std::string line) {
  if (!line.empty() && line.back() == '\n') line.pop_back();
  return line;
}

}  // namespace

CommandDecision decide_command(std::string_view payload, const CommandPermissions& permissions,
                               const std::string& config_source) {
  CommandDecision decision;
  ipcs::Request request;
  try {
    request = ipcs::parse_request(payload, kMaxCommandBytes);
  } catch (const ipcs::ProtocolError& e) {
    decision.id = e.id();
    decision.refusal = payload_of(ipcs::encode_error_reply(e));
    return decision;
  }
  decision.id = request.id;
  const bool reload = request.op == ipcs::Op::Reload;
  const bool recalibrate = request.op == ipcs::Op::Recalibrate;
  const std::string op(ipcs::to_string(request.op));
  if (!reload && !recalibrate) {
    decision.refusal = payload_of(ipcs::encode_error_reply(
        request.id, ipcs::ErrorCode::Forbidden,
        op + ": not a command of the bridge; the command topic takes reload and recalibrate "
             "(what tofcompd reports is published on the other topics)"));
    return decision;
  }
  if ((reload && !permissions.reload) || (recalibrate && !permissions.recalibrate)) {
    decision.refusal = payload_of(ipcs::encode_error_reply(
        request.id, ipcs::ErrorCode::Forbidden,
        op + ": not allowed by this bridge: commands." + op + " is false in " + config_source));
    return decision;
  }
  nlohmann::json forward{{"op", op}};
  if (recalibrate && !request.args.empty()) forward["args"] = request.args;
  decision.request = std::move(forward);
  return decision;
}

std::string relay_reply(const std::optional<nlohmann::json>& id, const std::string& daemon_reply) {
  nlohmann::ordered_json reply = nlohmann::ordered_json::parse(daemon_reply);
  nlohmann::ordered_json fields = nlohmann::ordered_json::object();
  for (auto it = reply.begin(); it != reply.end(); ++it) {
    if (it.key() != "id" && it.key() != "ok") fields[it.key()] = it.value();
  }
  return payload_of(ipcs::encode_ok_reply(id, fields));
}

}  // namespace tofcomp::bridges::mqtt
