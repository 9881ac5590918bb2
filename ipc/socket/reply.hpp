// The lines tofcompd writes on its socket (docs/protocol.md): replies
// {"id":..,"ok":true,...} and {"id":..,"ok":false,"error":{"code":..,"message":..}}, and scan
// events {"event":"scan","scan":{...}}. Each is one line ending in '\n'; "id" is present when
// the request had one. Text that is not valid UTF-8 (quoted from a bad request) is written with
// U+FFFD in its place, so encoding never fails.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

#include "ipc/socket/protocol_error.hpp"

namespace tofcomp::ipc::socket {

// {"id":..,"ok":true} followed by the members of fields (an object), in their order.
std::string encode_ok_reply(
    const std::optional<nlohmann::json>& id,
    const nlohmann::ordered_json& fields = nlohmann::ordered_json::object());

std::string encode_error_reply(const std::optional<nlohmann::json>& id, ErrorCode code,
                               std::string_view message);
std::string encode_error_reply(const ProtocolError& error);

// {"id":..,"ok":true,"scan":<scan_json>}: the reply to latest; scan_json from encode_scan.
std::string encode_scan_reply(const std::optional<nlohmann::json>& id, std::string_view scan_json);

// {"event":"scan","scan":<scan_json>}: one scan of a subscription.
std::string encode_scan_event(std::string_view scan_json);

}  // namespace tofcomp::ipc::socket
