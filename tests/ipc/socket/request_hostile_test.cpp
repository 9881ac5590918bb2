// The request parser on lines built to hurt it (issue 15): nesting deep enough to overflow the
// stack of a recursive copy, a key given twice, bytes hidden after a NUL. Each is refused with a
// bad_request naming what is wrong, within the largest max_request_bytes the daemon allows.
#include <gtest/gtest.h>

#include <string>

#include "ipc/socket/request.hpp"

namespace tofcomp::ipc::socket {
namespace {

// The largest max_request_bytes tofcompd's configuration allows (outputs.socket).
constexpr std::size_t kLargestAllowedRequest = 1u << 20;

ProtocolError refusal(const std::string& line) {
  try {
    parse_request(line, kLargestAllowedRequest);
  } catch (const ProtocolError& e) {
    return e;
  }
  ADD_FAILURE() << "accepted: " << line.substr(0, 80);
  return ProtocolError(ErrorCode::Internal, "accepted");
}

// `depth` arrays nested in the recalibrate args, which the daemon receives as a copy.
std::string nested_args(int depth) {
  return R"({"op":"recalibrate","args":{"a":)" + std::string(static_cast<std::size_t>(depth), '[') +
         std::string(static_cast<std::size_t>(depth), ']') + "}}";
}

TEST(HostileRequest, NestingOf200000LevelsIsRefusedNotACrash) {
  const std::string line = nested_args(200000);
  ASSERT_LE(line.size(), kLargestAllowedRequest);
  const ProtocolError e = refusal(line);
  EXPECT_EQ(e.code(), ErrorCode::BadRequest);
  EXPECT_EQ(std::string(e.what()),
            "request: nested deeper than 32 levels of objects and arrays (no request needs more "
            "than 3)");
}

TEST(HostileRequest, NestingUpToTheLimitIsParsed) {
  // The request object and args take two levels: 30 more arrays make 32.
  const Request r = parse_request(nested_args(30), kLargestAllowedRequest);
  EXPECT_EQ(r.op, Op::Recalibrate);
  EXPECT_EQ(refusal(nested_args(31)).code(), ErrorCode::BadRequest);
}

TEST(HostileRequest, AKeyGivenTwiceIsRefused) {
  const ProtocolError e = refusal(R"({"op":"status","op":"reload"})");
  EXPECT_EQ(e.code(), ErrorCode::BadRequest);
  EXPECT_EQ(std::string(e.what()), "'op': given twice in one object; a key may appear once");
  // In a nested object too; the same key in two objects is no fault.
  EXPECT_EQ(refusal(R"({"op":"recalibrate","args":{"recording":"a","recording":"b"}})").code(),
            ErrorCode::BadRequest);
  EXPECT_EQ(parse_request(R"({"op":"recalibrate","args":{"op":{"op":1}}})").op, Op::Recalibrate);
}

TEST(HostileRequest, BytesAfterANulAreRefused) {
  const std::string line = std::string(R"({"op":"status"})") + '\0' + R"({"op":"reload"})";
  const ProtocolError e = refusal(line);
  EXPECT_EQ(e.code(), ErrorCode::BadRequest);
  EXPECT_EQ(std::string(e.what()),
            "request: a NUL byte at offset 15; a request is one line of JSON text");
}

}  // namespace
}  // namespace tofcomp::ipc::socket
