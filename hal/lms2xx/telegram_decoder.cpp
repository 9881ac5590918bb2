#include "hal/lms2xx/telegram_decoder.hpp"

#include <algorithm>

#include "hal/lms2xx/crc16.hpp"

namespace tofcomp::hal::lms2xx {

TelegramDecoder::TelegramDecoder(Sender sender) : sender_(sender) {}

void TelegramDecoder::reset() {
  buffer_.clear();
  position_ = 0;
  failed_frame_end_ = 0;
  ack_expected_ = false;
  in_garbage_run_ = false;
}

void TelegramDecoder::feed(std::span<const std::uint8_t> bytes, const Sink& sink) {
  buffer_.insert(buffer_.end(), bytes.begin(), bytes.end());
  decode(sink, false);
}

void TelegramDecoder::flush_idle(const Sink& sink) { decode(sink, true); }

bool TelegramDecoder::address_is_plausible(std::uint8_t address) const {
  const bool from_device = (address & kReplyFlag) != 0;
  return sender_ == Sender::Device ? from_device : !from_device;
}

void TelegramDecoder::discard_byte() {
  ++counters_.garbage_bytes;
  if (!in_garbage_run_) ++counters_.garbage_runs;
  in_garbage_run_ = true;
  ++position_;
}

void TelegramDecoder::fail_frame(std::size_t frame_end) {
  // Give up the STX only; what follows is searched again.
  failed_frame_end_ = std::max(failed_frame_end_, frame_end);
  in_garbage_run_ = true;  // the failure is counted; the bytes after it continue the run
  ++position_;
}

void TelegramDecoder::decode(const Sink& sink, bool line_idle) {
  while (position_ < buffer_.size()) {
    const std::uint8_t byte = buffer_[position_];
    const bool inside_failed_frame = position_ < failed_frame_end_;
    if (byte != kStx) {
      if (!inside_failed_frame && ack_expected_ && (byte == kAck || byte == kNak)) {
        ack_expected_ = false;
        in_garbage_run_ = false;
        ++position_;
        DecoderEvent event;
        event.kind = byte == kAck ? DecoderEvent::Kind::Ack : DecoderEvent::Kind::Nak;
        ++(byte == kAck ? counters_.acks : counters_.naks);
        sink(event);
        continue;
      }
      discard_byte();
      continue;
    }
    const std::size_t available = buffer_.size() - position_;
    if (available >= 2 && !address_is_plausible(buffer_[position_ + 1])) {
      discard_byte();
      continue;
    }
    if (available < 4) {
      if (!line_idle) break;
      ++counters_.truncated;
      fail_frame(buffer_.size());
      continue;
    }
    const std::size_t payload = get_u16(buffer_, position_ + 2);
    if (payload == 0 || payload > kMaxPayloadBytes) {
      ++counters_.length_errors;
      fail_frame(position_ + 4);
      continue;
    }
    const std::size_t frame_bytes = payload + kFrameOverheadBytes - 1;  // LEN counts CMD
    if (available < frame_bytes) {
      if (!line_idle) break;
      ++counters_.truncated;
      fail_frame(buffer_.size());
      continue;
    }
    const std::span<const std::uint8_t> frame(buffer_.data() + position_, frame_bytes);
    const std::uint16_t crc = get_u16(frame, frame_bytes - 2);
    if (sick_crc16(frame.first(frame_bytes - 2)) != crc) {
      ++counters_.crc_errors;
      fail_frame(position_ + frame_bytes);
      continue;
    }
    scratch_.address = frame[1];
    scratch_.command = frame[4];
    scratch_.data.assign(frame.begin() + kHeaderBytes, frame.end() - 2);
    position_ += frame_bytes;
    in_garbage_run_ = false;
    ++counters_.telegrams;
    DecoderEvent event;
    event.kind = DecoderEvent::Kind::Telegram;
    event.telegram = &scratch_;
    sink(event);
  }
  // Keep the buffer short: drop what has been consumed.
  if (position_ > 0) {
    buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(position_));
    failed_frame_end_ = failed_frame_end_ > position_ ? failed_frame_end_ - position_ : 0;
    position_ = 0;
  }
}

}  // namespace tofcomp::hal::lms2xx
