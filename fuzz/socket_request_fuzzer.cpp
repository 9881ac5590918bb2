// libFuzzer target for tofcompd's socket request parser: arbitrary bytes as one request line.
// Properties checked besides "no crash, no sanitizer report": the parser ends in a Request or a
// ProtocolError and throws nothing else; an error's message is not empty and starts with the
// field at fault ("name: ..." or "'name': ..."); too_long exactly when the line passes the
// limit; a parsed request obeys the documented limits; and the reply the server would write
// for either outcome is one line of valid JSON carrying the right code and id. Lines up to the
// largest max_request_bytes the daemon allows (1 MiB) are tried, deep nesting among them.
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "ipc/socket/reply.hpp"
#include "ipc/socket/request.hpp"
#include "ipc/socket/server_defaults.hpp"

namespace {

using namespace tofcomp::ipc::socket;

void check(bool condition) {
  if (!condition) std::abort();
}

// The reply is one '\n'-terminated line that parses as a JSON object.
nlohmann::json check_line(const std::string& line) {
  check(!line.empty() && line.back() == '\n');
  check(line.find('\n') == line.size() - 1);
  const auto doc = nlohmann::json::parse(line, nullptr, false);
  check(doc.is_object());
  return doc;
}

void check_request(const Request& r, std::size_t limit, std::size_t size) {
  check(size <= limit);
  if (r.id) check(r.id->is_string() || r.id->is_number_integer());
  if (r.beams) check(r.beams->first <= r.beams->last && r.beams->last <= kMaxBeamIndex);
  check(r.every >= 1 && r.every <= kMaxEvery);
  check(r.args.is_object());
  const auto doc = check_line(encode_ok_reply(r.id));
  check(doc.value("ok", false));
  check(r.id ? doc.contains("id") && doc["id"] == *r.id : !doc.contains("id"));
}

void check_error(const ProtocolError& e, std::size_t limit, std::size_t size) {
  const std::string_view message = e.what();
  check(!message.empty());
  check(message.find(": ") != std::string_view::npos);
  check((e.code() == ErrorCode::TooLong) == (size > limit));
  const auto doc = check_line(encode_error_reply(e));
  check(!doc.value("ok", true));
  check(doc["error"]["code"] == std::string(to_string(e.code())));
  check(e.id() ? doc.contains("id") && doc["id"] == *e.id() : !doc.contains("id"));
}

// The limit of the parse: by the first byte of the input, the default (0-63), the largest the
// daemon's configuration allows (64-127, where deep nesting and long lines fit), or a small one
// so that too_long is reached (128-255).
std::size_t limit_for(std::uint8_t selector) {
  if (selector < 64) return kDefaultMaxRequestBytes;
  if (selector < 128) return kLargestMaxRequestBytes;
  return 64 + selector % 64;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::size_t limit = limit_for(data[0]);
  const std::string_view line(reinterpret_cast<const char*>(data + 1), size - 1);
  try {
    check_request(parse_request(line, limit), limit, line.size());
  } catch (const ProtocolError& e) {
    check_error(e, limit, line.size());
  } catch (...) {
    std::abort();  // nothing but a ProtocolError may leave the parser
  }
  return 0;
}
