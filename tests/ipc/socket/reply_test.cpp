// Reply and event lines, byte for byte: the envelope's order, the id echoed or left out, the
// error object, and text that is not UTF-8 made safe.
#include "ipc/socket/reply.hpp"

#include <gtest/gtest.h>

namespace tofcomp::ipc::socket {
namespace {

using nlohmann::json;
using nlohmann::ordered_json;

TEST(Reply, OkReplyPutsIdAndOkFirstThenTheFieldsInOrder) {
  EXPECT_EQ(encode_ok_reply(json(7), ordered_json{{"message", "reloaded"}, {"a", 1}}),
            "{\"id\":7,\"ok\":true,\"message\":\"reloaded\",\"a\":1}\n");
  EXPECT_EQ(encode_ok_reply(json("x")), "{\"id\":\"x\",\"ok\":true}\n");
}

TEST(Reply, NoIdInTheRequestMeansNoIdInTheReply) {
  EXPECT_EQ(encode_ok_reply(std::nullopt, ordered_json{{"subscription", nullptr}}),
            "{\"ok\":true,\"subscription\":null}\n");
}

TEST(Reply, ErrorReplyCarriesCodeAndMessage) {
  EXPECT_EQ(encode_error_reply(json(3), ErrorCode::BadRange, "beams: first 10 is after last 5"),
            "{\"id\":3,\"ok\":false,\"error\":{\"code\":\"bad_range\",\"message\":\"beams: first "
            "10 is after last 5\"}}\n");
  const ProtocolError e(ErrorCode::UnknownOp, "op: 'x' is not an op", json("r"));
  EXPECT_EQ(encode_error_reply(e),
            "{\"id\":\"r\",\"ok\":false,\"error\":{\"code\":\"unknown_op\",\"message\":\"op: "
            "'x' is not an op\"}}\n");
}

TEST(Reply, MessageWithBytesThatAreNotUtf8IsStillOneValidJsonLine) {
  const std::string line =
      encode_error_reply(std::nullopt, ErrorCode::BadRequest, "op: '\xff\xfe' \n is not an op");
  ASSERT_EQ(line.back(), '\n');
  EXPECT_EQ(line.find('\n'), line.size() - 1);  // the message's line break is escaped
  const json parsed = json::parse(line);
  EXPECT_EQ(parsed["error"]["message"], "op: '\xEF\xBF\xBD\xEF\xBF\xBD' \n is not an op");
}

TEST(Reply, ScanReplyAndEventSpliceTheEncodedScan) {
  EXPECT_EQ(encode_scan_reply(json(1), R"({"sequence":4})"),
            "{\"id\":1,\"ok\":true,\"scan\":{\"sequence\":4}}\n");
  EXPECT_EQ(encode_scan_reply(std::nullopt, R"({"sequence":4})"),
            "{\"ok\":true,\"scan\":{\"sequence\":4}}\n");
  EXPECT_EQ(encode_scan_event(R"({"sequence":4})"),
            "{\"event\":\"scan\",\"scan\":{\"sequence\":4}}\n");
}

}  // namespace
}  // namespace tofcomp::ipc::socket
