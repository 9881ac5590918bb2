// Scan subscription over the blocking client.
#include "ipc/socket/subscription.hpp"

namespace tofcomp::ipc::socket {

ScanSubscription::ScanSubscription(SocketClient& client, std::optional<BeamRange> beams,
                                   std::uint32_t every, Duration timeout)
    : client_(client) {
  nlohmann::json request{{"op", "subscribe"}, {"every", every}};
  if (beams) request["beams"] = {beams->first, beams->last};
  const nlohmann::json reply = client_.call(request, timeout);
  acknowledged_ = reply.value("subscription", nlohmann::json());
}

std::optional<nlohmann::json> ScanSubscription::next(Duration timeout) {
  auto message = client_.read_message(timeout);
  if (!message) return std::nullopt;
  if (message->is_object() && message->value("event", "") == "scan" && message->contains("scan")) {
    return std::move((*message)["scan"]);
  }
  std::string text = message->dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  if (text.size() > 200) text = text.substr(0, 200) + "...";
  throw core::Error("expected a scan event from tofcompd at " + client_.path() + ", got " + text);
}

void ScanSubscription::unsubscribe(Duration timeout) {
  client_.call({{"op", "unsubscribe"}}, timeout);
}

}  // namespace tofcomp::ipc::socket
