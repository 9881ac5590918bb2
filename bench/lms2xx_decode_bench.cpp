// Decode rate of the LMS 2xx codec: 0xB0 telegrams of 361 values (180° at 0.5°) through the
// streaming decoder and the scan parser, in scans per second, against the LMS 200's 75 scans/s.
// Bytes arrive in reads of 4096 bytes, as the host driver reads them.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <random>

#include "hal/lms2xx/messages.hpp"
#include "hal/lms2xx/scan_telegram.hpp"
#include "hal/lms2xx/telegram_decoder.hpp"

namespace {

using namespace tofcomp::hal::lms2xx;

std::vector<std::uint8_t> scan_stream(int scans, int values, double garbage_fraction) {
  std::mt19937 rng(1);
  std::uniform_int_distribution<int> range(2900, 3100);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<std::uint8_t> wire;
  for (int s = 0; s < scans; ++s) {
    ScanTelegram scan;
    for (int v = 0; v < values; ++v) {
      scan.distance_codes.push_back(static_cast<std::uint16_t>(range(rng)));
      scan.flags.push_back(0);
    }
    auto bytes =
        encode_telegram(Telegram{0x80, kScanReply, encode_scan_data(scan, MeasuringMode::Range8m)});
    if (u(rng) < garbage_fraction) bytes.back() ^= 0x55;  // a corrupted CRC
    wire.insert(wire.end(), bytes.begin(), bytes.end());
  }
  return wire;
}

void decode(benchmark::State& state, double garbage_fraction) {
  const int kScans = 256;
  const auto wire = scan_stream(kScans, 361, garbage_fraction);
  std::size_t decoded = 0;
  for (auto _ : state) {
    TelegramDecoder decoder(Sender::Device);
    for (std::size_t at = 0; at < wire.size(); at += 4096) {
      const std::size_t n = std::min<std::size_t>(4096, wire.size() - at);
      decoder.feed(std::span(wire.data() + at, n), [&](const DecoderEvent& e) {
        if (e.kind != DecoderEvent::Kind::Telegram) return;
        const ScanTelegram scan = decode_scan_data(e.telegram->data, MeasuringMode::Range8m);
        benchmark::DoNotOptimize(scan.distance_codes.data());
        ++decoded;
      });
    }
  }
  state.counters["scans_per_s"] =
      benchmark::Counter(static_cast<double>(decoded), benchmark::Counter::kIsRate);
  state.counters["times_lms200_rate"] =
      benchmark::Counter(static_cast<double>(decoded) / 75.0, benchmark::Counter::kIsRate);
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(wire.size()));
}

void BM_DecodeCleanScans(benchmark::State& state) {
  decode(state, 0.0);
}
void BM_DecodeScansWithCrcErrors(benchmark::State& state) {
  decode(state, 0.05);
}

BENCHMARK(BM_DecodeCleanScans);
BENCHMARK(BM_DecodeScansWithCrcErrors);

}  // namespace
