// What the library states about itself: its version, its error type, the flags' names, and the
// compact decoder for programs that read frames themselves.
#include <utility>

#include "client/public_scan.hpp"
#include "core/error.hpp"
#include "ipc/default_places.hpp"
#include "ipc/socket/compact_frame.hpp"
#include "ipc/socket/protocol_constants.hpp"
#include "tofcomp/client.hpp"

namespace tofcomp::client {

using client_detail::public_scan;

// The header states the protocol this library speaks; the protocol code is the one source of it.
static_assert(TOFCOMP_PROTOCOL_VERSION_MAJOR == ipc::socket::kProtocolVersionMajor &&
              TOFCOMP_PROTOCOL_VERSION_MINOR == ipc::socket::kProtocolVersionMinor);

Error::Error(ErrorKind kind, const std::string& message, std::string daemon_code)
    : std::runtime_error(message), kind_(kind), daemon_code_(std::move(daemon_code)) {}

const char* library_version() {
  return TOFCOMP_CLIENT_VERSION_STRING;
}

std::vector<std::string> flag_names(std::uint16_t flags) {
  return ipc::beam_flag_names(flags);
}

std::string default_socket_path() {
  return ipc::socket_to_read(ipc::current_user_environment()).string();
}

std::string default_ring_name() {
  return ipc::ring_to_read(ipc::current_user_environment());
}

Scan decode_compact(const void* bytes, std::size_t size) {
  if (bytes == nullptr && size != 0) throw Error(ErrorKind::InvalidArgument, "compact frame: null");
  try {
    const auto received =
        ipc::socket::decode_compact_frame(std::string_view(static_cast<const char*>(bytes), size));
    return public_scan(received.scan, received.span);
  } catch (const core::Error& e) {
    throw Error(ErrorKind::BadData, e.what());
  }
}

}  // namespace tofcomp::client
