// The request parser on bad requests: every error code it gives, with the field at fault named
// at the start of the message, and the id carried when it was readable.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "ipc/socket/request.hpp"

namespace tofcomp::ipc::socket {
namespace {

struct BadRequestCase {
  std::string line;
  ErrorCode code;
  std::string message_start;         // the field named, first
  std::optional<nlohmann::json> id;  // the id the error carries
};

void PrintTo(const BadRequestCase& c, std::ostream* os) {
  *os << c.line.substr(0, 80);
}

class RequestError : public ::testing::TestWithParam<BadRequestCase> {};

TEST_P(RequestError, CodeFieldAndId) {
  const BadRequestCase& c = GetParam();
  try {
    parse_request(c.line);
    FAIL() << "parsed: " << c.line;
  } catch (const ProtocolError& e) {
    EXPECT_EQ(to_string(e.code()), to_string(c.code));
    EXPECT_EQ(std::string(e.what()).substr(0, c.message_start.size()), c.message_start) << e.what();
    EXPECT_EQ(e.id(), c.id) << e.what();
    // What came from the request is escaped: no control character reaches the message.
    for (const char ch : std::string(e.what())) {
      EXPECT_FALSE(static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f) << e.what();
    }
  }
}

using nlohmann::json;

INSTANTIATE_TEST_SUITE_P(
    EveryFault, RequestError,
    ::testing::Values(
        BadRequestCase{"{oops", ErrorCode::BadRequest, "request: not valid JSON", {}},
        BadRequestCase{"", ErrorCode::BadRequest, "request: not valid JSON", {}},
        BadRequestCase{R"({"op":"status"} {"op":"stats"})",
                       ErrorCode::BadRequest,
                       "request: not valid JSON",
                       {}},
        BadRequestCase{"{\"op\":\"\xff\"}", ErrorCode::BadRequest, "request: not valid JSON", {}},
        BadRequestCase{
            "[1,2]", ErrorCode::BadRequest, "request: must be a JSON object, not an array", {}},
        BadRequestCase{
            "42", ErrorCode::BadRequest, "request: must be a JSON object, not a number", {}},
        BadRequestCase{R"({"id":1})", ErrorCode::BadRequest, "op: missing", json(1)},
        BadRequestCase{R"({"op":"latest","beams":[1e400,2]})",
                       ErrorCode::BadRequest,
                       "request: not valid JSON: number overflow parsing '1e400'",
                       {}},
        BadRequestCase{R"({"op":"status","id":123456789012345678901234567890})",
                       ErrorCode::BadRequest,
                       "id: must be a string or an integer, not a number",
                       {}},
        BadRequestCase{R"({"id":"q","op":5})", ErrorCode::BadRequest,
                       "op: must be a string, not an integer", json("q")},
        BadRequestCase{R"({"op":"fetch","id":"x"})", ErrorCode::UnknownOp,
                       "op: 'fetch' is not an op", json("x")},
        // A NUL, a line end or an escape sequence sent as JSON escapes (issue 53: "\u0000" cut
        // the message at the NUL) reaches the message escaped, whole.
        BadRequestCase{R"({"op":"status","a\u0000b":1})", ErrorCode::BadRequest,
                       "'a\\x00b': not a field of op 'status' (its fields: id, op)", {}},
        BadRequestCase{R"({"op":"fe\ntch\u001b[2J"})", ErrorCode::UnknownOp,
                       "op: 'fe\\ntch\\x1B[2J' is not an op; the ops are", {}},
        BadRequestCase{"{\"op\":\"status\"\t\x01}", ErrorCode::BadRequest,
                       "request: not valid JSON", {}},
        BadRequestCase{R"({"op":"LATEST","id":2})", ErrorCode::UnknownOp,
                       "op: 'LATEST' is not an op", json(2)},
        BadRequestCase{R"({"op":"subscribe","format":"cbor"})", ErrorCode::BadRequest,
                       "format: 'cbor' is not a format; the formats are json, compact", {}},
        BadRequestCase{R"({"op":"subscribe","format":1})", ErrorCode::BadRequest,
                       "format: must be a string, not an integer", {}},
        BadRequestCase{R"({"op":"latest","format":"compact"})", ErrorCode::BadRequest,
                       "'format': not a field of op 'latest' (its fields: id, op, beams)", {}},
        BadRequestCase{R"({"op":"status","id":3,"beams":[0,1]})", ErrorCode::BadRequest,
                       "'beams': not a field of op 'status' (its fields: id, op)", json(3)},
        BadRequestCase{R"({"op":"latest","every":2})",
                       ErrorCode::BadRequest,
                       "'every': not a field of op 'latest' (its fields: id, op, beams)",
                       {}},
        BadRequestCase{R"({"op":"latest","beams":[5]})",
                       ErrorCode::BadRequest,
                       "beams: must be [first, last], two integers, not an array of 1",
                       {}},
        BadRequestCase{R"({"op":"latest","beams":"0:5"})",
                       ErrorCode::BadRequest,
                       "beams: must be [first, last], two integers, not a string",
                       {}},
        BadRequestCase{R"({"op":"latest","beams":[5,"x"]})",
                       ErrorCode::BadRequest,
                       "beams[1]: must be an integer, not a string",
                       {}},
        BadRequestCase{R"({"op":"latest","beams":[1.5,3]})",
                       ErrorCode::BadRequest,
                       "beams[0]: must be an integer, not a number with a fraction",
                       {}},
        BadRequestCase{R"({"id":9,"op":"latest","beams":[10,5]})", ErrorCode::BadRange,
                       "beams: first 10 is after last 5", json(9)},
        BadRequestCase{R"({"op":"latest","beams":[-1,5]})",
                       ErrorCode::BadRange,
                       "beams[0]: -1 is outside 0..65535",
                       {}},
        BadRequestCase{R"({"op":"latest","beams":[0,65536]})",
                       ErrorCode::BadRange,
                       "beams[1]: 65536 is outside 0..65535",
                       {}},
        BadRequestCase{R"({"op":"subscribe","every":0})",
                       ErrorCode::BadRange,
                       "every: 0 is outside 1..1000000",
                       {}},
        BadRequestCase{R"({"op":"subscribe","every":18446744073709551615})",
                       ErrorCode::BadRange,
                       "every: 18446744073709551615 is outside 1..1000000",
                       {}},
        BadRequestCase{R"({"op":"subscribe","every":2.0})",
                       ErrorCode::BadRequest,
                       "every: must be an integer",
                       {}},
        BadRequestCase{R"({"op":"subscribe","every":null})",
                       ErrorCode::BadRequest,
                       "every: must be an integer, not a null",
                       {}},
        BadRequestCase{R"({"op":"recalibrate","args":[1]})",
                       ErrorCode::BadRequest,
                       "args: must be an object, not an array",
                       {}},
        BadRequestCase{R"({"id":{"a":1},"op":"status"})",
                       ErrorCode::BadRequest,
                       "id: must be a string or an integer, not an object",
                       {}},
        BadRequestCase{R"({"id":1.25,"op":"status"})",
                       ErrorCode::BadRequest,
                       "id: must be a string or an integer, not a number",
                       {}},
        BadRequestCase{R"({"id":")" + std::string(300, 'i') + R"(","op":"status"})",
                       ErrorCode::BadRequest,
                       "id: 300 bytes, more than the 256",
                       {}},
        BadRequestCase{R"({"op":"status","id":")" + std::string(4200, 'i') + R"("})",
                       ErrorCode::TooLong,
                       "request: 4223 bytes, more than the limit of 4096",
                       {}}));

TEST(RequestErrorLimit, TheLimitIsTheCallers) {
  const std::string line = R"({"op":"status"})";  // 15 bytes
  EXPECT_NO_THROW(parse_request(line, 15));
  try {
    parse_request(line, 14);
    FAIL();
  } catch (const ProtocolError& e) {
    EXPECT_EQ(e.code(), ErrorCode::TooLong);
    EXPECT_STREQ(e.what(), "request: 15 bytes, more than the limit of 14 bytes");
  }
}

TEST(RequestErrorLimit, LongFieldNamesAndOpsAreQuotedShortened) {
  const std::string name(500, 'n');
  try {
    parse_request(R"({"op":")" + name + R"("})");
    FAIL();
  } catch (const ProtocolError& e) {
    EXPECT_EQ(e.code(), ErrorCode::UnknownOp);
    EXPECT_LT(std::string(e.what()).size(), 200u) << e.what();
  }
}

TEST(ErrorCodeNames, RoundTripAndUnknownNames) {
  const std::vector<std::pair<ErrorCode, std::string>> names{
      {ErrorCode::BadRequest, "bad_request"},  {ErrorCode::UnknownOp, "unknown_op"},
      {ErrorCode::TooLong, "too_long"},        {ErrorCode::BadRange, "bad_range"},
      {ErrorCode::Unavailable, "unavailable"}, {ErrorCode::Refused, "refused"},
      {ErrorCode::Internal, "internal"},       {ErrorCode::Forbidden, "forbidden"}};
  for (const auto& [code, name] : names) {
    EXPECT_EQ(to_string(code), name);
    EXPECT_EQ(error_code_from_string(name), code);
  }
  EXPECT_FALSE(error_code_from_string("BadRequest").has_value());
  EXPECT_FALSE(error_code_from_string("").has_value());
}

}  // namespace
}  // namespace tofcomp::ipc::socket
