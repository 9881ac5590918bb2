// Wire names of the protocol's error codes.
#include "ipc/socket/protocol_error.hpp"

#include <array>
#include <utility>

namespace tofcomp::ipc::socket {

namespace {

constexpr std::array<std::pair<ErrorCode, std::string_view>, 8> kNames{{
    {ErrorCode::BadRequest, "bad_request"},
    {ErrorCode::UnknownOp, "unknown_op"},
    {ErrorCode::TooLong, "too_long"},
    {ErrorCode::BadRange, "bad_range"},
    {ErrorCode::Unavailable, "unavailable"},
    {ErrorCode::Refused, "refused"},
    {ErrorCode::Internal, "internal"},
    {ErrorCode::Forbidden, "forbidden"},
}};

}  // namespace

std::string_view to_string(ErrorCode code) {
  for (const auto& [c, name] : kNames) {
    if (c == code) return name;
  }
  return "internal";
}

std::optional<ErrorCode> error_code_from_string(std::string_view name) {
  for (const auto& [c, n] : kNames) {
    if (n == name) return c;
  }
  return std::nullopt;
}

ProtocolError::ProtocolError(ErrorCode code, const std::string& message,
                             std::optional<nlohmann::json> id)
    : core::Error(message), code_(code), id_(std::move(id)) {}

}  // namespace tofcomp::ipc::socket
