#include "hal/lms2xx/telegram_decoder.hpp"

#include <gtest/gtest.h>

#include <random>

#include "hal/lms2xx/messages.hpp"

namespace tofcomp::hal::lms2xx {
namespace {

using Bytes = std::vector<std::uint8_t>;

struct Collected {
  std::vector<Telegram> telegrams;
  int acks = 0;
  int naks = 0;
  TelegramDecoder::Sink sink() {
    return [this](const DecoderEvent& e) {
      if (e.kind == DecoderEvent::Kind::Telegram) telegrams.push_back(*e.telegram);
      if (e.kind == DecoderEvent::Kind::Ack) ++acks;
      if (e.kind == DecoderEvent::Kind::Nak) ++naks;
    };
  }
};

Telegram reply_with(std::uint8_t code, Bytes data) { return make_reply(code, data, 0x10); }

Bytes concat(std::initializer_list<Bytes> parts) {
  Bytes out;
  for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

TEST(TelegramDecoder, DecodesTelegramsFedOneByteAtATime) {
  const Telegram a = reply_with(0xB0, {1, 2, 3, 4});
  const Telegram b = reply_with(0xA0, {0});
  const Bytes wire = concat({encode_telegram(a), encode_telegram(b)});
  TelegramDecoder decoder(Sender::Device);
  Collected got;
  for (const std::uint8_t byte : wire) decoder.feed(std::span(&byte, 1), got.sink());
  ASSERT_EQ(got.telegrams.size(), 2u);
  EXPECT_EQ(got.telegrams[0], a);
  EXPECT_EQ(got.telegrams[1], b);
  EXPECT_EQ(decoder.counters().faults(), 0u);
  EXPECT_EQ(decoder.pending_bytes(), 0u);
}

TEST(TelegramDecoder, SkipsGarbageAndCountsOneRun) {
  const Telegram a = reply_with(0xB1, {9, 9});
  TelegramDecoder decoder(Sender::Device);
  Collected got;
  decoder.feed(concat({Bytes{0x55, 0xAA, 0x00, 0xFF}, encode_telegram(a)}), got.sink());
  ASSERT_EQ(got.telegrams.size(), 1u);
  EXPECT_EQ(decoder.counters().garbage_bytes, 4u);
  EXPECT_EQ(decoder.counters().garbage_runs, 1u);
}

TEST(TelegramDecoder, RejectsACorruptedCrcAndKeepsTheNextTelegram) {
  const Telegram a = reply_with(0xB0, {1, 2, 3});
  const Telegram b = reply_with(0xB0, {4, 5, 6});
  Bytes bad = encode_telegram(a);
  bad.back() ^= 0x01;
  TelegramDecoder decoder(Sender::Device);
  Collected got;
  decoder.feed(concat({bad, encode_telegram(b)}), got.sink());
  ASSERT_EQ(got.telegrams.size(), 1u);
  EXPECT_EQ(got.telegrams[0], b);
  EXPECT_EQ(decoder.counters().crc_errors, 1u);
}

TEST(TelegramDecoder, FindsATelegramSwallowedByACorruptedLength) {
  // The first frame's LEN claims 20 bytes; the real telegram after it lies inside that span.
  const Telegram b = reply_with(0xB0, {7, 8});
  const Bytes bogus{0x02, 0x80, 20, 0x00, 0xB0};
  TelegramDecoder decoder(Sender::Device);
  Collected got;
  decoder.feed(concat({bogus, encode_telegram(b), Bytes(30, 0x00)}), got.sink());
  ASSERT_EQ(got.telegrams.size(), 1u);
  EXPECT_EQ(got.telegrams[0], b);
  EXPECT_EQ(decoder.counters().crc_errors, 1u);
}

TEST(TelegramDecoder, CountsAnImpossibleLength) {
  TelegramDecoder decoder(Sender::Device);
  Collected got;
  decoder.feed(Bytes{0x02, 0x80, 0xFF, 0x7F, 0x00}, got.sink());
  EXPECT_EQ(decoder.counters().length_errors, 1u);
  EXPECT_TRUE(got.telegrams.empty());
}

TEST(TelegramDecoder, AnIdleLineTruncatesAPartialFrame) {
  const Bytes whole = encode_telegram(reply_with(0xB0, {1, 2, 3, 4, 5, 6}));
  TelegramDecoder decoder(Sender::Device);
  Collected got;
  decoder.feed(std::span(whole).first(6), got.sink());
  EXPECT_EQ(decoder.counters().truncated, 0u);  // more may come
  decoder.flush_idle(got.sink());
  EXPECT_EQ(decoder.counters().truncated, 1u);
  EXPECT_EQ(decoder.pending_bytes(), 0u);
  decoder.feed(whole, got.sink());
  EXPECT_EQ(got.telegrams.size(), 1u);
}

TEST(TelegramDecoder, AckAndNakCountOnlyAfterARequest) {
  TelegramDecoder decoder(Sender::Device);
  Collected got;
  decoder.feed(Bytes{kAck}, got.sink());  // unsolicited: garbage
  EXPECT_EQ(got.acks, 0);
  decoder.expect_ack();
  decoder.feed(Bytes{kAck, kAck}, got.sink());  // the second is unsolicited again
  EXPECT_EQ(got.acks, 1);
  decoder.expect_ack();
  decoder.feed(Bytes{kNak}, got.sink());
  EXPECT_EQ(got.naks, 1);
  EXPECT_EQ(decoder.counters().garbage_bytes, 2u);
}

TEST(TelegramDecoder, AFrameFromTheWrongSideIsGarbage) {
  TelegramDecoder device_side(Sender::Host);
  Collected got;
  device_side.feed(encode_telegram(reply_with(0xB0, {1})), got.sink());
  EXPECT_TRUE(got.telegrams.empty());
  device_side.feed(encode_telegram(status_request()), got.sink());
  ASSERT_EQ(got.telegrams.size(), 1u);
  EXPECT_EQ(got.telegrams[0].command, 0x31);
}

TEST(TelegramDecoder, RandomCorruptionNeverYieldsABadTelegram) {
  // 2,000 telegrams with random damage: every telegram the decoder accepts is one that was sent
  // intact, and every intact telegram not adjacent to damage is found.
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> byte(0, 255);
  std::vector<Telegram> sent;
  Bytes wire;
  std::size_t damaged = 0;
  for (int i = 0; i < 2000; ++i) {
    Bytes data(static_cast<std::size_t>(1 + i % 40));
    for (auto& b : data) b = static_cast<std::uint8_t>(byte(rng));
    const Telegram t = reply_with(0xB0, data);
    Bytes frame = encode_telegram(t);
    if (i % 10 == 3) {
      frame[static_cast<std::size_t>(byte(rng)) % frame.size()] ^= 0x5A;
      ++damaged;
    } else {
      sent.push_back(t);
    }
    wire.insert(wire.end(), frame.begin(), frame.end());
  }
  TelegramDecoder decoder(Sender::Device);
  Collected got;
  decoder.feed(wire, got.sink());
  decoder.flush_idle(got.sink());
  std::size_t matched = 0;
  for (const Telegram& t : got.telegrams) {
    while (matched < sent.size() && !(sent[matched] == t)) ++matched;
    ASSERT_LT(matched, sent.size()) << "a telegram that was never sent intact was accepted";
  }
  EXPECT_GE(got.telegrams.size(), sent.size() - damaged);
  EXPECT_GE(decoder.counters().faults(), damaged);
}

}  // namespace
}  // namespace tofcomp::hal::lms2xx
