// libFuzzer target for the LMS 2xx codec: arbitrary bytes, in arbitrary read sizes, through the
// streaming decoder (both directions) and every reply parser. Properties checked besides "no
// crash, no sanitizer report": every telegram the decoder accepts lies intact in the input;
// parsers fail only with core::InvalidInput; an idle flush leaves nothing pending.
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <span>

#include "core/error.hpp"
#include "hal/lms2xx/messages.hpp"
#include "hal/lms2xx/scan_telegram.hpp"
#include "hal/lms2xx/telegram_decoder.hpp"

namespace {

using namespace tofcomp::hal::lms2xx;

void check(bool condition) {
  if (!condition) std::abort();
}

void parse_every_way(const Telegram& t) {
  const auto attempt = [](auto&& parse) {
    try {
      parse();
    } catch (const tofcomp::core::InvalidInput&) {
    }
  };
  for (const auto mode :
       {MeasuringMode::Range8m, MeasuringMode::Range16m, MeasuringMode::Range32m}) {
    attempt([&] { decode_scan_data(t.data, mode); });
  }
  attempt([&] { parse_mode_switch_reply(t); });
  attempt([&] { parse_variant_reply(t); });
  attempt([&] { parse_type_reply(t); });
  attempt([&] { parse_configuration_reply(t); });
  attempt([&] { parse_configure_reply(t); });
  attempt([&] { parse_status_reply(t); });
}

void run(std::span<const std::uint8_t> input, std::size_t chunk, Sender sender) {
  TelegramDecoder decoder(sender);
  std::uint64_t telegrams = 0;
  const auto sink = [&](const DecoderEvent& e) {
    if (e.kind != DecoderEvent::Kind::Telegram) return;
    ++telegrams;
    const auto wire = encode_telegram(*e.telegram);
    check(std::search(input.begin(), input.end(), wire.begin(), wire.end()) != input.end());
    parse_every_way(*e.telegram);
  };
  for (std::size_t at = 0; at < input.size(); at += chunk) {
    if (at % 7 == 3) decoder.expect_ack();
    decoder.feed(input.subspan(at, std::min(chunk, input.size() - at)), sink);
  }
  decoder.flush_idle(sink);
  check(decoder.pending_bytes() == 0);
  check(decoder.counters().telegrams == telegrams);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::size_t chunk = 1 + data[0] % 64;
  const std::span<const std::uint8_t> input(data + 1, size - 1);
  run(input, chunk, Sender::Device);
  run(input, chunk, Sender::Host);
  return 0;
}
