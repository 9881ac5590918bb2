// The request parser: strict (unknown fields and wrong types are errors, each naming its
// field), total (every input ends in a Request or a ProtocolError).
#include "ipc/socket/request.hpp"

#include <array>
#include <functional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "core/printable_text.hpp"

namespace tofcomp::ipc::socket {

namespace {

using nlohmann::json;

struct OpSpec {
  Op op;
  std::string_view name;
  std::vector<std::string_view> fields;  // besides id and op
};

const std::array<OpSpec, 8>& op_specs() {
  static const std::array<OpSpec, 8> specs{{
      {Op::Latest, "latest", {"beams"}},
      {Op::Subscribe, "subscribe", {"beams", "every", "format"}},
      {Op::Unsubscribe, "unsubscribe", {}},
      {Op::Status, "status", {}},
      {Op::Stats, "stats", {}},
      {Op::Reload, "reload", {}},
      {Op::Recalibrate, "recalibrate", {"args"}},
      {Op::Hello, "hello", {}},
  }};
  return specs;
}

// A piece of the input quoted in a message: at most 64 bytes of it, control characters escaped
// (a "\u0000" in a JSON string is a NUL once parsed).
std::string quote_input(std::string_view text) {
  constexpr std::size_t kMax = 64;
  if (text.size() <= kMax) return "'" + core::printable(text) + "'";
  return "'" + core::printable(text.substr(0, kMax)) + "...'";
}

// The parser's complaint without its "[json.exception...] " prefix, at most 160 bytes.
std::string json_complaint(const json::exception& e) {
  std::string what = e.what();
  const auto bracket = what.find("] ");
  if (bracket != std::string::npos) what.erase(0, bracket + 2);
  if (what.size() > 160) what = what.substr(0, 160) + "...";
  return core::printable(what);  // it quotes what it last read of the input
}

// Thrown by the parse guard below: a request the JSON parser itself would accept, refused.
struct GuardFault {
  std::string message;
};

// Watches the JSON parser's events (nlohmann's parser callback) and stops the parse at the first
// object or array nested deeper than kMaxRequestDepth, and at a key given twice in one object
// (JSON leaves that undefined; nlohmann would keep the last silently).
class ParseGuard {
 public:
  bool operator()(int /*depth*/, json::parse_event_t event, json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
      case json::parse_event_t::array_start:
        if (++depth_ > kMaxRequestDepth) {
          throw GuardFault{"request: nested deeper than " + std::to_string(kMaxRequestDepth) +
                           " levels of objects and arrays (no request needs more than 3)"};
        }
        if (event == json::parse_event_t::object_start) keys_.emplace_back();
        break;
      case json::parse_event_t::object_end:
        --depth_;
        keys_.pop_back();
        break;
      case json::parse_event_t::array_end:
        --depth_;
        break;
      case json::parse_event_t::key:
        if (!keys_.empty() && !keys_.back().insert(parsed.get<std::string>()).second) {
          throw GuardFault{quote_input(parsed.get<std::string>()) +
                           ": given twice in one object; a key may appear once"};
        }
        break;
      case json::parse_event_t::value:
        break;
    }
    return true;
  }

 private:
  int depth_ = 0;
  std::vector<std::set<std::string>> keys_;  // of each open object
};

class Parser {
 public:
  explicit Parser(const json& doc) : doc_(doc) {}

  Request parse() {
    read_id();
    read_op();
    check_fields();
    if (const auto it = doc_.find("beams"); it != doc_.end()) request_.beams = read_beams(*it);
    if (const auto it = doc_.find("every"); it != doc_.end()) {
      request_.every = read_integer(*it, "every", 1, kMaxEvery);
    }
    if (const auto it = doc_.find("format"); it != doc_.end()) request_.format = read_format(*it);
    if (const auto it = doc_.find("args"); it != doc_.end()) {
      if (!it->is_object())
        fail(ErrorCode::BadRequest, "args: must be an object, not " + kind(*it));
      request_.args = *it;
    }
    return request_;
  }

 private:
  const json& doc_;
  Request request_;
  const OpSpec* spec_ = nullptr;

  [[noreturn]] void fail(ErrorCode code, const std::string& message) const {
    throw ProtocolError(code, message, request_.id);
  }

  static std::string kind(const json& v) {
    if (v.is_number_integer()) return "an integer";
    if (v.is_number_float()) return "a number with a fraction or exponent";
    const std::string name = v.type_name();
    return (name == "array" || name == "object" ? "an " : "a ") + name;
  }

  void read_id() {
    const auto it = doc_.find("id");
    if (it == doc_.end()) return;
    if (it->is_string()) {
      const auto& text = it->get_ref<const std::string&>();
      if (text.size() > kMaxIdBytes) {
        fail(ErrorCode::BadRequest, "id: " + std::to_string(text.size()) +
                                        " bytes, more than the " + std::to_string(kMaxIdBytes) +
                                        " a string id may have");
      }
    } else if (!it->is_number_integer()) {
      fail(ErrorCode::BadRequest, "id: must be a string or an integer, not " + kind(*it));
    }
    request_.id = *it;
  }

  void read_op() {
    const auto it = doc_.find("op");
    if (it == doc_.end()) fail(ErrorCode::BadRequest, "op: missing; every request names its op");
    if (!it->is_string()) fail(ErrorCode::BadRequest, "op: must be a string, not " + kind(*it));
    const auto& name = it->get_ref<const std::string&>();
    for (const auto& spec : op_specs()) {
      if (spec.name == name) {
        spec_ = &spec;
        request_.op = spec.op;
        return;
      }
    }
    std::string ops;
    for (const auto& spec : op_specs()) ops += (ops.empty() ? "" : ", ") + std::string(spec.name);
    fail(ErrorCode::UnknownOp, "op: " + quote_input(name) + " is not an op; the ops are " + ops);
  }

  void check_fields() const {
    for (const auto& [key, value] : doc_.items()) {
      if (key == "id" || key == "op") continue;
      bool known = false;
      for (const auto field : spec_->fields) known = known || field == key;
      if (known) continue;
      std::string allowed = "id, op";
      for (const auto field : spec_->fields) allowed += ", " + std::string(field);
      fail(ErrorCode::BadRequest, quote_input(key) + ": not a field of op '" +
                                      std::string(spec_->name) + "' (its fields: " + allowed + ")");
    }
  }

  // An integer within [min, max]: bad_request when not an integer, bad_range when outside.
  std::uint32_t read_integer(const json& v, const std::string& field, std::uint32_t min,
                             std::uint32_t max) const {
    if (!v.is_number_integer()) {
      fail(ErrorCode::BadRequest, field + ": must be an integer, not " + kind(v));
    }
    if (v.is_number_unsigned()) {
      const auto value = v.get<std::uint64_t>();
      if (value >= min && value <= max) return static_cast<std::uint32_t>(value);
      fail(ErrorCode::BadRange, field + ": " + std::to_string(value) + " is outside " +
                                    std::to_string(min) + ".." + std::to_string(max));
    }
    fail(ErrorCode::BadRange, field + ": " + std::to_string(v.get<std::int64_t>()) +
                                  " is outside " + std::to_string(min) + ".." +
                                  std::to_string(max));
  }

  ScanFormat read_format(const json& v) const {
    if (!v.is_string()) fail(ErrorCode::BadRequest, "format: must be a string, not " + kind(v));
    for (const ScanFormat format : {ScanFormat::Json, ScanFormat::Compact}) {
      if (v.get_ref<const std::string&>() == to_string(format)) return format;
    }
    fail(ErrorCode::BadRequest, "format: " + quote_input(v.get_ref<const std::string&>()) +
                                    " is not a format; the formats are json, compact");
  }

  BeamRange read_beams(const json& v) const {
    if (!v.is_array() || v.size() != 2) {
      fail(ErrorCode::BadRequest,
           "beams: must be [first, last], two integers, not " +
               (v.is_array() ? "an array of " + std::to_string(v.size()) : kind(v)));
    }
    const BeamRange range{read_integer(v[0], "beams[0]", 0, kMaxBeamIndex),
                          read_integer(v[1], "beams[1]", 0, kMaxBeamIndex)};
    if (range.first > range.last) {
      fail(ErrorCode::BadRange, "beams: first " + std::to_string(range.first) + " is after last " +
                                    std::to_string(range.last));
    }
    return range;
  }
};

}  // namespace

std::string_view to_string(Op op) {
  for (const auto& spec : op_specs()) {
    if (spec.op == op) return spec.name;
  }
  return "unknown";
}

std::string_view to_string(ScanFormat format) {
  return format == ScanFormat::Compact ? "compact" : "json";
}

Request parse_request(std::string_view line, std::size_t max_bytes) {
  if (line.size() > max_bytes) {
    throw ProtocolError(ErrorCode::TooLong, "request: " + std::to_string(line.size()) +
                                                " bytes, more than the limit of " +
                                                std::to_string(max_bytes) + " bytes");
  }
  if (const std::size_t nul = line.find('\0'); nul != std::string_view::npos) {
    throw ProtocolError(ErrorCode::BadRequest, "request: a NUL byte at offset " +
                                                   std::to_string(nul) +
                                                   "; a request is one line of JSON text");
  }
  json doc;
  try {
    ParseGuard guard;
    doc = json::parse(line.begin(), line.end(), std::ref(guard));
  } catch (const GuardFault& fault) {
    throw ProtocolError(ErrorCode::BadRequest, fault.message);
  } catch (const json::exception& e) {  // parse_error, or out_of_range for a number too large
    throw ProtocolError(ErrorCode::BadRequest, "request: not valid JSON: " + json_complaint(e));
  }
  if (!doc.is_object()) {
    throw ProtocolError(ErrorCode::BadRequest,
                        std::string("request: must be a JSON object, not ") +
                            (doc.is_array() ? "an array" : std::string("a ") + doc.type_name()));
  }
  return Parser(doc).parse();
}

}  // namespace tofcomp::ipc::socket
