// libFuzzer target for tofcompd's socket request parser: arbitrary bytes as one request line.
// Properties checked besides "no crash, no sanitizer report": the parser ends in a Request or a
// ProtocolError and throws nothing else; an error's message is not empty and starts with the
// field at fault ("name: ..." or "'name': ..."); too_long exactly when the line passes the
// limit; a parsed request obeys the documented limits; and the reply the server would write
// for either outcome is one line of valid JSON carrying the right code and id.
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "ipc/socket/reply.hpp"
#include "ipc/socket/request.hpp"

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

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // The first byte picks the limit: the default, or a small one so that too_long is reached.
  if (size == 0) return 0;
  const std::size_t limit = data[0] < 128 ? kDefaultMaxRequestBytes : 64 + data[0] % 64;
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
