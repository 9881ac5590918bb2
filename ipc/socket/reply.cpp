// Reply and event lines: the envelope through nlohmann::ordered_json (so "id" and "ok" come
// first), the scan spliced in as the text encode_scan made.
#include "ipc/socket/reply.hpp"

namespace tofcomp::ipc::socket {

namespace {

using nlohmann::ordered_json;

ordered_json envelope(const std::optional<nlohmann::json>& id, bool ok) {
  ordered_json reply = ordered_json::object();
  if (id) reply["id"] = *id;
  reply["ok"] = ok;
  return reply;
}

std::string dump(const ordered_json& value) {
  return value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace

std::string encode_ok_reply(const std::optional<nlohmann::json>& id, const ordered_json& fields) {
  ordered_json reply = envelope(id, true);
  for (const auto& [key, value] : fields.items()) reply[key] = value;
  return dump(reply) + '\n';
}

std::string encode_error_reply(const std::optional<nlohmann::json>& id, ErrorCode code,
                               std::string_view message) {
  ordered_json reply = envelope(id, false);
  reply["error"] = ordered_json{{"code", to_string(code)}, {"message", message}};
  return dump(reply) + '\n';
}

std::string encode_error_reply(const ProtocolError& error) {
  return encode_error_reply(error.id(), error.code(), error.what());
}

std::string encode_scan_reply(const std::optional<nlohmann::json>& id, std::string_view scan_json) {
  std::string line = dump(envelope(id, true));
  line.pop_back();  // the closing brace
  line += ",\"scan\":";
  line += scan_json;
  line += "}\n";
  return line;
}

std::string encode_scan_event(std::string_view scan_json) {
  std::string line;
  line.reserve(scan_json.size() + 32);
  line += "{\"event\":\"scan\",\"scan\":";
  line += scan_json;
  line += "}\n";
  return line;
}

}  // namespace tofcomp::ipc::socket
