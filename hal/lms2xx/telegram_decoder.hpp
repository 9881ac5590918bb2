// The streaming decoder of LMS 2xx telegrams: bytes in as they arrive from the line, whole
// telegrams, ACKs and NAKs out. It resynchronises after garbage, truncated telegrams, corrupted
// lengths and CRC errors without losing a good telegram that follows, and counts each.
//
// Resynchronisation: a frame that fails (bad CRC, impossible length, truncated by an idle line)
// gives up only its STX; the bytes after it are searched again for the next STX, so a telegram
// swallowed by a corrupted length field is still found. An ACK or NAK byte is taken as one only
// where one can come: after a request (expect_ack) and outside a failed frame's bytes.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "hal/lms2xx/telegram.hpp"

namespace tofcomp::hal::lms2xx {

// Who sends the telegrams the decoder reads: the device (address 0x80 + device address) or the
// host (address below 0x80). The address byte of a frame from the other side is garbage.
enum class Sender { Device, Host };

struct DecoderCounters {
  std::uint64_t telegrams = 0;      // telegrams with a good CRC
  std::uint64_t acks = 0;
  std::uint64_t naks = 0;
  std::uint64_t garbage_bytes = 0;  // bytes outside any good frame
  std::uint64_t garbage_runs = 0;   // stretches of consecutive garbage bytes
  std::uint64_t crc_errors = 0;     // complete frames whose CRC did not match
  std::uint64_t length_errors = 0;  // frames whose LEN was 0 or beyond kMaxPayloadBytes
  std::uint64_t truncated = 0;      // frames cut short (the line went idle mid-frame)

  // Every anomaly the decoder saw: garbage runs, CRC and length errors, truncated frames.
  std::uint64_t faults() const { return garbage_runs + crc_errors + length_errors + truncated; }
};

struct DecoderEvent {
  enum class Kind { Ack, Nak, Telegram };
  Kind kind = Kind::Telegram;
  const Telegram* telegram = nullptr;  // for Kind::Telegram; valid during the callback only
};

class TelegramDecoder {
 public:
  using Sink = std::function<void(const DecoderEvent&)>;

  explicit TelegramDecoder(Sender sender);

  // Decodes `bytes` after what came before, calling sink for each ACK, NAK and telegram.
  void feed(std::span<const std::uint8_t> bytes, const Sink& sink);
  // The line has gone quiet: a partial frame will not be completed. Counts it as truncated and
  // searches its bytes for telegrams.
  void flush_idle(const Sink& sink);
  // The next ACK or NAK byte answers a request (a host decoder calls this after each request).
  void expect_ack() { ack_expected_ = true; }
  // Forgets buffered bytes (the link was reopened); keeps the counters.
  void reset();

  const DecoderCounters& counters() const { return counters_; }
  // Bytes held waiting for the rest of a frame.
  std::size_t pending_bytes() const { return buffer_.size() - position_; }

 private:
  Sender sender_;
  std::vector<std::uint8_t> buffer_;
  std::size_t position_ = 0;
  std::size_t failed_frame_end_ = 0;  // bytes before this belong to a failed frame
  bool ack_expected_ = false;
  bool in_garbage_run_ = false;
  Telegram scratch_;
  DecoderCounters counters_;

  void decode(const Sink& sink, bool line_idle);
  bool address_is_plausible(std::uint8_t address) const;
  void discard_byte();
  void fail_frame(std::size_t frame_end);
};

}  // namespace tofcomp::hal::lms2xx
