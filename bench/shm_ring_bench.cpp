// Rates of the shared-memory ring for 361-beam scans (180° at 0.5°), against the LMS 200's 75
// scans/s: the writer's publish, a reader's latest(), and a reader's read_new() draining a full
// ring, in the same process (the copies are the same across processes).
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <cmath>
#include <string>

#include "ipc/ring/ring_reader.hpp"
#include "ipc/ring/ring_writer.hpp"

namespace {

using namespace tofcomp::ipc;

constexpr std::uint32_t kSlots = 64;
constexpr std::size_t kBeams = 361;

std::string bench_ring_name(const char* what) {
  return "/tofcomp-bench-" + std::to_string(::getpid()) + "-" + what;
}

CompensatedScan scan_of_361_beams(std::uint64_t sequence) {
  CompensatedScan scan;
  scan.sequence = sequence;
  scan.timestamp_ns = 1'700'000'000'000'000'000;
  scan.junction_c = 27.5;
  scan.junction_std_c = 0.05;
  scan.case_c = 25.0;
  scan.resolution_deg = 0.5;
  scan.calibration_id = 1;
  scan.beams.resize(kBeams);
  for (std::size_t b = 0; b < kBeams; ++b) {
    BeamValue& v = scan.beams[b];
    v.raw_mm = 3000.0 + static_cast<double>(b);
    v.compensated_mm = v.raw_mm - 12.5;
    v.window_mm = b % 10 == 0 ? std::nan("") : v.raw_mm - 12.0;
    v.window_std_mm = b % 10 == 0 ? std::nan("") : 0.8;
    v.mode_posterior = {0.7f, 0.2f, 0.1f, 0.0f};
    v.flags = b % 10 == 0 ? kBeamWindowRestarting : 0;
    v.mode_count = 3;
  }
  return scan;
}

void rate_counters(benchmark::State& state, std::uint64_t scans) {
  state.counters["scans_per_s"] =
      benchmark::Counter(static_cast<double>(scans), benchmark::Counter::kIsRate);
  state.counters["times_lms200_rate"] =
      benchmark::Counter(static_cast<double>(scans) / 75.0, benchmark::Counter::kIsRate);
}

void BM_Publish361(benchmark::State& state) {
  ring::RingWriter writer(bench_ring_name("publish"), kSlots, ring::kDefaultMaxBeams);
  CompensatedScan scan = scan_of_361_beams(0);
  for (auto _ : state) {
    writer.publish(scan);
    ++scan.sequence;
  }
  rate_counters(state, writer.published());
}
BENCHMARK(BM_Publish361);

void BM_ReadLatest361(benchmark::State& state) {
  const std::string name = bench_ring_name("latest");
  ring::RingWriter writer(name, kSlots, ring::kDefaultMaxBeams);
  writer.publish(scan_of_361_beams(0));
  ring::RingReader reader(name);
  std::uint64_t scans = 0;
  for (auto _ : state) {
    auto scan = reader.latest();
    benchmark::DoNotOptimize(scan->beams.data());
    ++scans;
  }
  rate_counters(state, scans);
}
BENCHMARK(BM_ReadLatest361);

void BM_ReadNewFullRing361(benchmark::State& state) {
  const std::string name = bench_ring_name("drain");
  ring::RingWriter writer(name, kSlots, ring::kDefaultMaxBeams);
  for (std::uint64_t s = 0; s < kSlots; ++s) writer.publish(scan_of_361_beams(s));
  ring::RingReader reader(name);
  std::uint64_t scans = 0;
  for (auto _ : state) {
    reader.rewind_to_oldest();
    const ring::ReadBatch batch = reader.read_new();
    benchmark::DoNotOptimize(batch.scans.data());
    scans += batch.scans.size();
  }
  rate_counters(state, scans);
}
BENCHMARK(BM_ReadNewFullRing361);

}  // namespace
