// tofcompd's compensation path, from a scan telegram's last byte to its publication: the
// decoder and the scan parser (hal/lms2xx), the conversion to millimetres (daemon/), the
// pipeline (junction temperature, Eq. 8, sliding-window EM on each of 361 beams: realtime/),
// the shared-memory ring and the socket's JSON encoding. Counters: ranges per second and the
// multiple of the LMS 200's 75 scans/s; p50 and p99 latency per scan; CPU time per second of
// data at 75 scans/s; resident memory. One run as fast as the path goes, one paced at 75 scans/s.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <fstream>
#include <random>
#include <thread>

#include "daemon/scan_conversion.hpp"
#include "hal/lms2xx/messages.hpp"
#include "hal/lms2xx/scan_telegram.hpp"
#include "hal/lms2xx/telegram_decoder.hpp"
#include "io/calibration_file.hpp"
#include "ipc/ring/ring_writer.hpp"
#include "ipc/socket/scan_json.hpp"
#include "realtime/compensation_pipeline.hpp"

namespace {

namespace lms = tofcomp::hal::lms2xx;
using Clock = std::chrono::steady_clock;

constexpr int kBeams = 361;
constexpr double kScanRate = 75.0;

// Scan telegrams as the emulated LMS 200 sends them: a wall 3 m away, two lasing modes.
std::vector<std::vector<std::uint8_t>> telegrams(int count) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::bernoulli_distribution second_mode(0.45);
  std::vector<std::vector<std::uint8_t>> out;
  for (int s = 0; s < count; ++s) {
    lms::ScanTelegram scan;
    for (int b = 0; b < kBeams; ++b) {
      const double range = 3000.0 + (second_mode(rng) ? 2.7 : -1.8) + noise(rng);
      scan.distance_codes.push_back(static_cast<std::uint16_t>(std::lround(range)));
      scan.flags.push_back(0);
    }
    out.push_back(lms::encode_telegram(lms::Telegram{
        0x80, lms::kScanReply, lms::encode_scan_data(scan, lms::MeasuringMode::Range8m)}));
  }
  return out;
}

double resident_mb() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  }
  return 0.0;
}

void compensation_path(benchmark::State& state, bool paced, bool encode_json) {
  const auto wire = telegrams(256);
  auto calibration =
      std::make_shared<const tofcomp::core::Calibration>(tofcomp::io::read_calibration_file(
          std::string(TOFCOMP_SOURCE_ROOT) + "/config/calibration.yaml"));
  tofcomp::realtime::CompensationPipeline pipeline;
  pipeline.set_calibration(calibration, 1);
  tofcomp::ipc::ring::RingWriter ring("/tofcomp-bench-" + std::to_string(::getpid()));
  lms::TelegramDecoder decoder(lms::Sender::Device);
  const lms::Variant variant{180, 50};
  std::vector<double> latencies_us;
  std::size_t bytes_out = 0;
  std::uint64_t scans = 0;
  const auto start = Clock::now();
  for (auto _ : state) {
    const auto& bytes = wire[scans % wire.size()];
    if (paced) {
      std::this_thread::sleep_until(start + std::chrono::duration_cast<Clock::duration>(
                                                std::chrono::duration<double>(scans / kScanRate)));
    }
    const double time_s = static_cast<double>(scans) / kScanRate;
    if (scans % 75 == 0) pipeline.on_case_reading(time_s, 25.0 + 1e-4 * static_cast<double>(scans));
    const auto arrived = Clock::now();  // the telegram's last byte is in
    decoder.feed(std::span(bytes.data(), bytes.size()), [&](const lms::DecoderEvent& e) {
      if (e.kind != lms::DecoderEvent::Kind::Telegram) return;
      lms::HostScan host;
      host.sequence = scans;
      host.received = arrived;
      host.scan = lms::decode_scan_data(e.telegram->data, lms::MeasuringMode::Range8m);
      const auto raw = tofcomp::daemon::to_raw_scan(host, variant, time_s);
      const auto published = pipeline.on_scan(raw);
      ring.publish(published);
      if (!encode_json) return;  // no subscriber: the socket encodes nothing
      const std::string json = tofcomp::ipc::socket::encode_scan(
          published, tofcomp::ipc::socket::beams_exactly(std::nullopt, published.beams.size()));
      bytes_out += json.size();
    });
    latencies_us.push_back(
        std::chrono::duration<double, std::micro>(Clock::now() - arrived).count());
    ++scans;
  }
  std::sort(latencies_us.begin(), latencies_us.end());
  const auto at = [&](double q) {
    return latencies_us[static_cast<std::size_t>(q * static_cast<double>(latencies_us.size() - 1))];
  };
  double mean_us = 0.0;
  for (const double l : latencies_us) mean_us += l;
  mean_us /= static_cast<double>(latencies_us.size());
  state.counters["ranges_per_s"] =
      benchmark::Counter(static_cast<double>(scans * kBeams), benchmark::Counter::kIsRate);
  state.counters["times_lms200_rate"] =
      benchmark::Counter(static_cast<double>(scans) / kScanRate, benchmark::Counter::kIsRate);
  state.counters["p50_us"] = at(0.50);
  state.counters["p99_us"] = at(0.99);
  state.counters["cpu_ms_per_s_of_data"] = mean_us * kScanRate / 1000.0;
  state.counters["rss_mb"] = resident_mb();
  if (encode_json) {
    state.counters["json_bytes_per_scan"] =
        static_cast<double>(bytes_out) / static_cast<double>(scans);
  }
}

// Decoder, pipeline and ring: what every scan costs.
void BM_CompensationPathAsFastAsItGoes(benchmark::State& state) {
  compensation_path(state, false, false);
}
// The same with the socket's JSON encoding of all 361 beams (once per scan when at least one
// client subscribes to every beam).
void BM_CompensationPathWithSocketEncoding(benchmark::State& state) {
  compensation_path(state, false, true);
}
// Paced at 75 scans/s, with the socket's encoding: the latency a client sees at the real rate.
void BM_CompensationPathAtTheLms200Rate(benchmark::State& state) {
  compensation_path(state, true, true);
}

BENCHMARK(BM_CompensationPathAsFastAsItGoes)->Iterations(20000);
BENCHMARK(BM_CompensationPathWithSocketEncoding)->Iterations(20000);
BENCHMARK(BM_CompensationPathAtTheLms200Rate)->Iterations(1500)->UseRealTime();

}  // namespace
