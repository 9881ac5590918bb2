// tofcompd's compensation path, from a scan telegram's last byte to its publication: the
// decoder and the scan parser (hal/lms2xx), the conversion to millimetres (daemon/), the
// pipeline (junction temperature, Eq. 8, sliding-window EM on each of 361 beams: realtime/),
// the shared-memory ring and, with a subscriber of every beam, the socket's encoding (a JSON
// line or a compact frame) written to a connected Unix socket whose other end a reader thread
// drains, as a client does. Counters: ranges per second and the multiple of the LMS 200's 75
// scans/s; p50 and p99 latency per scan; CPU time per second of data at 75 scans/s; resident
// memory. Runs as fast as the path goes, and paced at 75 scans/s.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <fstream>
#include <optional>
#include <random>
#include <stdexcept>
#include <thread>

#include <sys/socket.h>
#include <unistd.h>

#include "daemon/scan_conversion.hpp"
#include "daemon/socket/scan_fanout.hpp"
#include "hal/lms2xx/messages.hpp"
#include "hal/lms2xx/scan_telegram.hpp"
#include "hal/lms2xx/telegram_decoder.hpp"
#include "io/calibration_file.hpp"
#include "ipc/ring/ring_writer.hpp"
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

// What the socket sends per scan: nothing (no client subscribed), every beam as a JSON event
// line, or every beam as a compact frame (docs/protocol.md).
enum class Subscriber { None, Json, Compact };

// A connected Unix stream socket pair whose far end a thread reads and discards until the near
// end closes: the kernel's copy of each scan to a client, without the client's decoding.
class DrainedSocket {
 public:
  DrainedSocket() {
    if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, ends_) != 0) {
      throw std::runtime_error("socketpair failed");
    }
    reader_ = std::thread([fd = ends_[1]] {
      std::array<char, kReadChunkBytes> chunk{};
      while (::read(fd, chunk.data(), chunk.size()) > 0) {
      }
    });
  }
  DrainedSocket(const DrainedSocket&) = delete;
  DrainedSocket& operator=(const DrainedSocket&) = delete;
  ~DrainedSocket() {
    ::close(ends_[0]);  // the reader's read returns 0
    reader_.join();
    ::close(ends_[1]);
  }
  void write_all(const std::string& bytes) {
    std::size_t sent = 0;
    while (sent < bytes.size()) {
      const ssize_t n = ::write(ends_[0], bytes.data() + sent, bytes.size() - sent);
      if (n <= 0) throw std::runtime_error("write to the subscriber's socket failed");
      sent += static_cast<std::size_t>(n);
    }
  }

 private:
  static constexpr std::size_t kReadChunkBytes = 1 << 16;
  int ends_[2] = {-1, -1};
  std::thread reader_;
};

double resident_mb() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  }
  return 0.0;
}

void compensation_path(benchmark::State& state, bool paced, Subscriber subscriber) {
  const auto wire = telegrams(256);
  auto calibration =
      std::make_shared<const tofcomp::core::Calibration>(tofcomp::io::read_calibration_file(
          std::string(TOFCOMP_SOURCE_ROOT) + "/config/calibration.yaml"));
  tofcomp::realtime::CompensationPipeline pipeline;
  pipeline.set_calibration(calibration, 1);
  tofcomp::ipc::ring::RingWriter ring("/tofcomp-bench-" + std::to_string(::getpid()));
  lms::TelegramDecoder decoder(lms::Sender::Device);
  std::optional<DrainedSocket> client;
  if (subscriber != Subscriber::None) client.emplace();
  tofcomp::daemon::socket::Subscription every_beam;  // every beam, every scan
  every_beam.format = subscriber == Subscriber::Compact ? tofcomp::ipc::socket::ScanFormat::Compact
                                                        : tofcomp::ipc::socket::ScanFormat::Json;
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
      if (subscriber == Subscriber::None) return;  // the socket encodes nothing
      // The daemon's own fan-out: one encoding per scan, whatever number of clients take it.
      tofcomp::daemon::socket::ScanFanout fanout(published);
      const auto bytes_sent = fanout.line_for(every_beam);
      client->write_all(*bytes_sent);
      bytes_out += bytes_sent->size();
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
  if (subscriber != Subscriber::None) {
    state.counters["bytes_per_scan"] =
        static_cast<double>(bytes_out) / static_cast<double>(scans);
  }
}

constexpr int kFlatOutScans = 20000;
constexpr int kPacedScans = 1500;  // 20 s at 75 scans/s

// Decoder, pipeline and ring: what every scan costs.
void BM_CompensationPathAsFastAsItGoes(benchmark::State& state) {
  compensation_path(state, false, Subscriber::None);
}
// The same with a subscriber of all 361 beams: the JSON line (encoded once per scan however
// many clients take it) or the compact frame, written to its socket.
void BM_CompensationPathWithJsonSubscriber(benchmark::State& state) {
  compensation_path(state, false, Subscriber::Json);
}
void BM_CompensationPathWithCompactSubscriber(benchmark::State& state) {
  compensation_path(state, false, Subscriber::Compact);
}
// Paced at 75 scans/s, with a subscriber: the latency a client sees at the real rate.
void BM_CompensationPathAtTheLms200RateJson(benchmark::State& state) {
  compensation_path(state, true, Subscriber::Json);
}
void BM_CompensationPathAtTheLms200RateCompact(benchmark::State& state) {
  compensation_path(state, true, Subscriber::Compact);
}

BENCHMARK(BM_CompensationPathAsFastAsItGoes)->Iterations(kFlatOutScans);
BENCHMARK(BM_CompensationPathWithJsonSubscriber)->Iterations(kFlatOutScans);
BENCHMARK(BM_CompensationPathWithCompactSubscriber)->Iterations(kFlatOutScans);
BENCHMARK(BM_CompensationPathAtTheLms200RateJson)->Iterations(kPacedScans)->UseRealTime();
BENCHMARK(BM_CompensationPathAtTheLms200RateCompact)->Iterations(kPacedScans)->UseRealTime();

}  // namespace
