// The request parser on well-formed requests: each op and each field read as written.
#include <gtest/gtest.h>

#include "ipc/socket/request.hpp"

namespace tofcomp::ipc::socket {
namespace {

TEST(RequestParse, LatestWithoutBeamsAsksForEveryBeamAndHasNoId) {
  const Request r = parse_request(R"({"op":"latest"})");
  EXPECT_EQ(r.op, Op::Latest);
  EXPECT_FALSE(r.id.has_value());
  EXPECT_FALSE(r.beams.has_value());
}

TEST(RequestParse, LatestWithBeamsAndIntegerId) {
  const Request r = parse_request(R"({"id":7,"op":"latest","beams":[10,20]})");
  EXPECT_EQ(r.op, Op::Latest);
  ASSERT_TRUE(r.id.has_value());
  EXPECT_EQ(*r.id, nlohmann::json(7));
  ASSERT_TRUE(r.beams.has_value());
  EXPECT_EQ(*r.beams, (BeamRange{10, 20}));
}

TEST(RequestParse, SubscribeWithStringIdRangeAndDecimation) {
  const Request r =
      parse_request(R"(  {"every": 5, "beams": [0, 360], "op": "subscribe", "id": "a-1"}  )");
  EXPECT_EQ(r.op, Op::Subscribe);
  EXPECT_EQ(*r.id, nlohmann::json("a-1"));
  EXPECT_EQ(*r.beams, (BeamRange{0, 360}));
  EXPECT_EQ(r.every, 5u);
}

TEST(RequestParse, SubscribeDefaultsToEveryScan) {
  EXPECT_EQ(parse_request(R"({"op":"subscribe"})").every, 1u);
}

TEST(RequestParse, SubscribeFormatDefaultsToJsonAndTakesCompact) {
  EXPECT_EQ(parse_request(R"({"op":"subscribe"})").format, ScanFormat::Json);
  EXPECT_EQ(parse_request(R"({"op":"subscribe","format":"json"})").format, ScanFormat::Json);
  EXPECT_EQ(parse_request(R"({"op":"subscribe","format":"compact"})").format, ScanFormat::Compact);
}

TEST(RequestParse, SingleBeamAndTheLimitsOfEachFieldAreAccepted) {
  EXPECT_EQ(*parse_request(R"({"op":"latest","beams":[180,180]})").beams, (BeamRange{180, 180}));
  EXPECT_EQ(*parse_request(R"({"op":"latest","beams":[0,65535]})").beams, (BeamRange{0, 65535}));
  EXPECT_EQ(parse_request(R"({"op":"subscribe","every":1000000})").every, 1000000u);
  EXPECT_EQ(*parse_request(R"({"op":"status","id":-9223372036854775808})").id,
            nlohmann::json(std::numeric_limits<std::int64_t>::min()));
}

TEST(RequestParse, EveryOpByName) {
  EXPECT_EQ(parse_request(R"({"op":"unsubscribe"})").op, Op::Unsubscribe);
  EXPECT_EQ(parse_request(R"({"op":"status"})").op, Op::Status);
  EXPECT_EQ(parse_request(R"({"op":"stats"})").op, Op::Stats);
  EXPECT_EQ(parse_request(R"({"op":"reload"})").op, Op::Reload);
  EXPECT_EQ(parse_request(R"({"op":"recalibrate"})").op, Op::Recalibrate);
  EXPECT_EQ(parse_request(R"({"op":"hello"})").op, Op::Hello);
  for (const Op op : {Op::Latest, Op::Subscribe, Op::Unsubscribe, Op::Status, Op::Stats, Op::Reload,
                      Op::Recalibrate, Op::Hello}) {
    const std::string line = R"({"op":")" + std::string(to_string(op)) + R"("})";
    EXPECT_EQ(parse_request(line).op, op) << line;
  }
}

TEST(RequestParse, RecalibrateArgsArePassedAsGivenAndDefaultToAnEmptyObject) {
  const Request with = parse_request(R"({"op":"recalibrate","args":{"reference_mm":2000.5}})");
  EXPECT_EQ(with.args, nlohmann::json({{"reference_mm", 2000.5}}));
  EXPECT_EQ(parse_request(R"({"op":"recalibrate"})").args, nlohmann::json::object());
}

TEST(RequestParse, ALineOfExactlyTheLimitIsParsed) {
  std::string line = R"({"op":"status","id":")";
  line += std::string(40, 'x') + "\"}";
  EXPECT_EQ(parse_request(line, line.size()).op, Op::Status);
}

}  // namespace
}  // namespace tofcomp::ipc::socket
