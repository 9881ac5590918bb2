// The C API over the C++ one: handles are the C++ objects, every exception becomes a status and
// this thread's last error message. Nothing throws across the C boundary.
#include <cstdlib>
#include <cstring>
#include <new>
#include <string>

#include "tofcomp/client.hpp"
#include "tofcomp/tofcomp_client.h"

struct tofcomp_connection {
  tofcomp::client::Connection connection;
};
struct tofcomp_ring {
  tofcomp::client::Ring ring;
};
struct tofcomp_scan {
  tofcomp::client::Scan scan;
};

namespace {

using tofcomp::client::BeamRange;
using tofcomp::client::Error;
using tofcomp::client::ErrorKind;
using Duration = tofcomp::client::Connection::Duration;

thread_local std::string last_error;
thread_local std::string last_daemon_code;

int fail(int status, const std::string& message, const std::string& daemon_code = {}) {
  last_error = message;
  last_daemon_code = daemon_code;
  return status;
}

// Runs f, which returns a status; an exception becomes its status and message.
template <typename F>
int guarded(F&& f) {
  try {
    return f();
  } catch (const Error& e) {
    return fail(static_cast<int>(e.kind()), e.what(), e.daemon_code());
  } catch (const std::bad_alloc&) {
    return fail(TOFCOMP_ERR_INTERNAL, "out of memory");
  } catch (const std::exception& e) {
    return fail(TOFCOMP_ERR_INTERNAL, std::string("internal error: ") + e.what());
  } catch (...) {
    return fail(TOFCOMP_ERR_INTERNAL, "internal error: an unknown exception");
  }
}

Duration milliseconds(int timeout_ms) {
  return Duration(timeout_ms < 0 ? 0 : timeout_ms);
}

// first..last as a range: both TOFCOMP_ALL_BEAMS for every beam.
std::optional<BeamRange> beam_range(int first, int last) {
  if (first == TOFCOMP_ALL_BEAMS && last == TOFCOMP_ALL_BEAMS) return std::nullopt;
  if (first < 0 || last < 0) {
    throw Error(ErrorKind::InvalidArgument,
                "beams: " + std::to_string(first) + ".." + std::to_string(last) +
                    ": indices are at least 0 (TOFCOMP_ALL_BEAMS for both: every beam)");
  }
  return BeamRange{static_cast<std::uint32_t>(first), static_cast<std::uint32_t>(last)};
}

int null_argument(const char* what) {
  return fail(TOFCOMP_ERR_INVALID_ARGUMENT, std::string(what) + ": must not be NULL");
}

int give_scan(tofcomp::client::Scan scan, tofcomp_scan** out) {
  *out = new tofcomp_scan{std::move(scan)};
  return TOFCOMP_OK;
}

}  // namespace

extern "C" {

const char* tofcomp_client_version(void) {
  return tofcomp::client::library_version();
}

const char* tofcomp_last_error(void) {
  return last_error.c_str();
}

const char* tofcomp_last_daemon_code(void) {
  return last_daemon_code.c_str();
}

int tofcomp_connect(const char* path, int timeout_ms, tofcomp_connection** out) {
  if (out == nullptr) return null_argument("out");
  *out = nullptr;
  return guarded([&] {
    *out = new tofcomp_connection{tofcomp::client::Connection(
        path != nullptr ? path : tofcomp::client::default_socket_path(), milliseconds(timeout_ms))};
    return TOFCOMP_OK;
  });
}

void tofcomp_disconnect(tofcomp_connection* connection) {
  delete connection;
}

int tofcomp_hello(const tofcomp_connection* connection, int* protocol_major, int* protocol_minor,
                  const char** daemon_version) {
  if (connection == nullptr) return null_argument("connection");
  const auto& hello = connection->connection.hello();
  if (protocol_major != nullptr) *protocol_major = hello.protocol_major;
  if (protocol_minor != nullptr) *protocol_minor = hello.protocol_minor;
  if (daemon_version != nullptr) *daemon_version = hello.daemon_version.c_str();
  return TOFCOMP_OK;
}

int tofcomp_latest(tofcomp_connection* connection, int first, int last, int timeout_ms,
                   tofcomp_scan** out) {
  if (connection == nullptr) return null_argument("connection");
  if (out == nullptr) return null_argument("out");
  *out = nullptr;
  return guarded([&] {
    return give_scan(
        connection->connection.latest(beam_range(first, last), milliseconds(timeout_ms)), out);
  });
}

int tofcomp_subscribe(tofcomp_connection* connection, int first, int last, unsigned every,
                      int format, int timeout_ms) {
  if (connection == nullptr) return null_argument("connection");
  if (format != TOFCOMP_FORMAT_JSON && format != TOFCOMP_FORMAT_COMPACT) {
    return fail(TOFCOMP_ERR_INVALID_ARGUMENT,
                "format: " + std::to_string(format) +
                    " is neither TOFCOMP_FORMAT_JSON nor TOFCOMP_FORMAT_COMPACT");
  }
  return guarded([&] {
    connection->connection.subscribe(beam_range(first, last), every,
                                     static_cast<tofcomp::client::Format>(format),
                                     milliseconds(timeout_ms));
    return TOFCOMP_OK;
  });
}

int tofcomp_next_scan(tofcomp_connection* connection, int timeout_ms, tofcomp_scan** out) {
  if (connection == nullptr) return null_argument("connection");
  if (out == nullptr) return null_argument("out");
  *out = nullptr;
  return guarded([&] {
    auto scan = connection->connection.next_scan(milliseconds(timeout_ms));
    return scan ? give_scan(std::move(*scan), out) : TOFCOMP_NO_SCAN;
  });
}

int tofcomp_unsubscribe(tofcomp_connection* connection, int timeout_ms) {
  if (connection == nullptr) return null_argument("connection");
  return guarded([&] {
    connection->connection.unsubscribe(milliseconds(timeout_ms));
    return TOFCOMP_OK;
  });
}

int tofcomp_call(tofcomp_connection* connection, const char* request_json, int timeout_ms,
                 char** reply_json) {
  if (connection == nullptr) return null_argument("connection");
  if (request_json == nullptr) return null_argument("request_json");
  if (reply_json == nullptr) return null_argument("reply_json");
  *reply_json = nullptr;
  return guarded([&] {
    const std::string reply = connection->connection.call(request_json, milliseconds(timeout_ms));
    char* copy = static_cast<char*>(std::malloc(reply.size() + 1));
    if (copy == nullptr) throw std::bad_alloc();
    std::memcpy(copy, reply.c_str(), reply.size() + 1);
    *reply_json = copy;
    return TOFCOMP_OK;
  });
}

void tofcomp_free_string(char* text) {
  std::free(text);
}

int tofcomp_ring_open(const char* name, tofcomp_ring** out) {
  if (out == nullptr) return null_argument("out");
  *out = nullptr;
  return guarded([&] {
    *out = new tofcomp_ring{
        tofcomp::client::Ring(name != nullptr ? name : tofcomp::client::default_ring_name())};
    return TOFCOMP_OK;
  });
}

void tofcomp_ring_close(tofcomp_ring* ring) {
  delete ring;
}

int tofcomp_ring_latest(tofcomp_ring* ring, tofcomp_scan** out) {
  if (ring == nullptr) return null_argument("ring");
  if (out == nullptr) return null_argument("out");
  *out = nullptr;
  return guarded([&] {
    auto scan = ring->ring.latest();
    return scan ? give_scan(std::move(*scan), out) : TOFCOMP_NO_SCAN;
  });
}

int tofcomp_ring_next(tofcomp_ring* ring, tofcomp_scan** out) {
  if (ring == nullptr) return null_argument("ring");
  if (out == nullptr) return null_argument("out");
  *out = nullptr;
  return guarded([&] {
    auto scan = ring->ring.next();
    return scan ? give_scan(std::move(*scan), out) : TOFCOMP_NO_SCAN;
  });
}

uint64_t tofcomp_ring_lost(const tofcomp_ring* ring) {
  return ring == nullptr ? 0 : ring->ring.lost();
}

int tofcomp_decode_compact(const void* bytes, size_t size, tofcomp_scan** out) {
  if (out == nullptr) return null_argument("out");
  *out = nullptr;
  return guarded([&] { return give_scan(tofcomp::client::decode_compact(bytes, size), out); });
}

void tofcomp_scan_free(tofcomp_scan* scan) {
  delete scan;
}

const tofcomp_scan_info* tofcomp_scan_get_info(const tofcomp_scan* scan) {
  return scan == nullptr ? nullptr : &scan->scan.info;
}

const tofcomp_beam* tofcomp_scan_beams(const tofcomp_scan* scan, size_t* count) {
  if (count != nullptr) *count = scan == nullptr ? 0 : scan->scan.beams.size();
  return scan == nullptr || scan->scan.beams.empty() ? nullptr : scan->scan.beams.data();
}

}  // extern "C"
