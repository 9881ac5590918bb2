// Compact frames: written and read byte by byte in little-endian order, so that the layout is the
// same on every host (docs/protocol.md gives the offsets).
#include "ipc/socket/compact_frame.hpp"

#include <bit>
#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "core/ray_timing.hpp"

namespace tofcomp::ipc::socket {

namespace {

// Offsets in the header (docs/protocol.md, "Compact frames").
constexpr std::size_t kOffsetVersion = 4;
constexpr std::size_t kOffsetHeaderBytes = 6;
constexpr std::size_t kOffsetFrameBytes = 8;
constexpr std::size_t kOffsetCalibrationId = 12;
constexpr std::size_t kOffsetSequence = 16;
constexpr std::size_t kOffsetDeviceSequence = 24;
constexpr std::size_t kOffsetTimestamp = 32;
constexpr std::size_t kOffsetJunction = 40;
constexpr std::size_t kOffsetJunctionStd = 48;
constexpr std::size_t kOffsetCase = 56;
constexpr std::size_t kOffsetStartAngle = 64;
constexpr std::size_t kOffsetResolution = 72;
constexpr std::size_t kOffsetBeamCount = 80;
constexpr std::size_t kOffsetFirstBeam = 84;
constexpr std::size_t kOffsetCount = 88;
constexpr std::size_t kOffsetReserved = 92;
constexpr std::size_t kOffsetFirstRay = 96;  // the rays' timing (core/ray_timing.hpp)
constexpr std::size_t kOffsetRayInterval = 104;
constexpr std::size_t kOffsetTurnPeriod = 112;
constexpr std::size_t kOffsetInterlacedTurns = 120;
constexpr std::size_t kOffsetRaysReserved = 124;
static_assert(kOffsetReserved + 4 == kOffsetFirstRay);
static_assert(kOffsetRaysReserved + 4 == kCompactHeaderBytes);

template <typename Unsigned>
void put(std::string& out, std::size_t offset, Unsigned value) {
  for (std::size_t i = 0; i < sizeof(Unsigned); ++i) {
    out[offset + i] = static_cast<char>((value >> (8 * i)) & 0xFFu);
  }
}

template <typename Unsigned>
Unsigned get(std::string_view in, std::size_t offset) {
  Unsigned value = 0;
  for (std::size_t i = 0; i < sizeof(Unsigned); ++i) {
    value |= static_cast<Unsigned>(static_cast<unsigned char>(in[offset + i])) << (8 * i);
  }
  return value;
}

void put_f64(std::string& out, std::size_t offset, double value) {
  put(out, offset, std::bit_cast<std::uint64_t>(value));
}
double get_f64(std::string_view in, std::size_t offset) {
  return std::bit_cast<double>(get<std::uint64_t>(in, offset));
}

[[noreturn]] void bad(const std::string& what) {
  throw core::InvalidInput("compact frame: " + what);
}

}  // namespace

std::string encode_compact_frame(const ipc::CompensatedScan& scan, BeamSpan span) {
  const std::size_t size = kCompactHeaderBytes + span.count * kCompactBytesPerBeam;
  std::string out(size, '\0');
  for (std::size_t i = 0; i < kCompactMagic.size(); ++i)
    out[i] = static_cast<char>(kCompactMagic[i]);
  put(out, kOffsetVersion, kCompactFrameVersion);
  put(out, kOffsetHeaderBytes, static_cast<std::uint16_t>(kCompactHeaderBytes));
  put(out, kOffsetFrameBytes, static_cast<std::uint32_t>(size));
  put(out, kOffsetCalibrationId, scan.calibration_id);
  put(out, kOffsetSequence, scan.sequence);
  put(out, kOffsetDeviceSequence, scan.device_sequence);
  put(out, kOffsetTimestamp, static_cast<std::uint64_t>(scan.timestamp_ns));
  put_f64(out, kOffsetJunction, scan.junction_c);
  put_f64(out, kOffsetJunctionStd, scan.junction_std_c);
  put_f64(out, kOffsetCase, scan.case_c);
  put_f64(out, kOffsetStartAngle, scan.start_angle_deg);
  put_f64(out, kOffsetResolution, scan.resolution_deg);
  put(out, kOffsetBeamCount, static_cast<std::uint32_t>(scan.beams.size()));
  put(out, kOffsetFirstBeam, static_cast<std::uint32_t>(span.first));
  put(out, kOffsetCount, static_cast<std::uint32_t>(span.count));
  put(out, kOffsetFirstRay, static_cast<std::uint64_t>(scan.rays.first_ray_ns));
  put_f64(out, kOffsetRayInterval, scan.rays.ray_interval_ns);
  put_f64(out, kOffsetTurnPeriod, scan.rays.turn_period_ns);
  put(out, kOffsetInterlacedTurns, scan.rays.interlaced_turns);
  const std::size_t flags_at = kCompactHeaderBytes + span.count * sizeof(float);
  for (std::size_t i = 0; i < span.count; ++i) {
    const BeamValue& beam = scan.beams[span.first + i];
    put(out, kCompactHeaderBytes + i * sizeof(float),
        std::bit_cast<std::uint32_t>(static_cast<float>(beam.compensated_mm)));
    put(out, flags_at + i * sizeof(std::uint16_t), beam.flags);
  }
  return out;
}

std::size_t compact_frame_size(std::string_view header) {
  if (header.size() < kCompactHeaderBytes) {
    bad(std::to_string(header.size()) + " bytes, fewer than the " +
        std::to_string(kCompactHeaderBytes) + " of its header");
  }
  for (std::size_t i = 0; i < kCompactMagic.size(); ++i) {
    if (static_cast<unsigned char>(header[i]) != kCompactMagic[i]) {
      bad("byte " + std::to_string(i) + " of the magic is not that of a compact frame");
    }
  }
  if (const auto version = get<std::uint16_t>(header, kOffsetVersion);
      version != kCompactFrameVersion) {
    bad("version (offset 4) is " + std::to_string(version) + "; this reader knows version " +
        std::to_string(kCompactFrameVersion));
  }
  if (const auto bytes = get<std::uint16_t>(header, kOffsetHeaderBytes);
      bytes != kCompactHeaderBytes) {
    bad("header size (offset 6) is " + std::to_string(bytes) + ", not " +
        std::to_string(kCompactHeaderBytes));
  }
  const auto beam_count = get<std::uint32_t>(header, kOffsetBeamCount);
  const auto first = get<std::uint32_t>(header, kOffsetFirstBeam);
  const auto count = get<std::uint32_t>(header, kOffsetCount);
  if (beam_count > kMaxCompactBeams) {
    bad("beam_count (offset 80) is " + std::to_string(beam_count) + ", more than the " +
        std::to_string(kMaxCompactBeams) + " a scan may have");
  }
  if (std::uint64_t{first} + count > beam_count) {
    bad("beams " + std::to_string(first) + " + " + std::to_string(count) +
        " (offsets 84, 88) reach beyond the scan's " + std::to_string(beam_count));
  }
  if (const auto turns = get<std::uint32_t>(header, kOffsetInterlacedTurns);
      turns > core::kMaxInterlacedTurns) {
    bad("interlaced_turns (offset 120) is " + std::to_string(turns) + ", more than " +
        std::to_string(core::kMaxInterlacedTurns));
  }
  const std::size_t size = kCompactHeaderBytes + std::size_t{count} * kCompactBytesPerBeam;
  if (const auto stated = get<std::uint32_t>(header, kOffsetFrameBytes); stated != size) {
    bad("frame size (offset 8) is " + std::to_string(stated) + " bytes; " + std::to_string(count) +
        " beams make " + std::to_string(size));
  }
  return size;
}

ReceivedScan decode_compact_frame(std::string_view frame) {
  const std::size_t size = compact_frame_size(frame);
  if (frame.size() != size) {
    bad(std::to_string(frame.size()) + " bytes where its header says " + std::to_string(size));
  }
  ReceivedScan received;
  ipc::CompensatedScan& scan = received.scan;
  scan.calibration_id = get<std::uint32_t>(frame, kOffsetCalibrationId);
  scan.sequence = get<std::uint64_t>(frame, kOffsetSequence);
  scan.device_sequence = get<std::uint64_t>(frame, kOffsetDeviceSequence);
  scan.timestamp_ns = static_cast<std::int64_t>(get<std::uint64_t>(frame, kOffsetTimestamp));
  scan.junction_c = get_f64(frame, kOffsetJunction);
  scan.junction_std_c = get_f64(frame, kOffsetJunctionStd);
  scan.case_c = get_f64(frame, kOffsetCase);
  scan.start_angle_deg = get_f64(frame, kOffsetStartAngle);
  scan.resolution_deg = get_f64(frame, kOffsetResolution);
  scan.rays.first_ray_ns = static_cast<std::int64_t>(get<std::uint64_t>(frame, kOffsetFirstRay));
  scan.rays.ray_interval_ns = get_f64(frame, kOffsetRayInterval);
  scan.rays.turn_period_ns = get_f64(frame, kOffsetTurnPeriod);
  scan.rays.interlaced_turns = get<std::uint32_t>(frame, kOffsetInterlacedTurns);
  received.span.first = get<std::uint32_t>(frame, kOffsetFirstBeam);
  received.span.count = get<std::uint32_t>(frame, kOffsetCount);
  constexpr double kNotSent = std::numeric_limits<double>::quiet_NaN();
  scan.beams.resize(get<std::uint32_t>(frame, kOffsetBeamCount));
  const std::size_t flags_at = kCompactHeaderBytes + received.span.count * sizeof(float);
  for (std::size_t i = 0; i < received.span.count; ++i) {
    BeamValue& beam = scan.beams[received.span.first + i];
    beam.compensated_mm =
        std::bit_cast<float>(get<std::uint32_t>(frame, kCompactHeaderBytes + i * sizeof(float)));
    beam.flags = get<std::uint16_t>(frame, flags_at + i * sizeof(std::uint16_t));
    beam.raw_mm = beam.window_mm = beam.window_std_mm = kNotSent;
  }
  return received;
}

}  // namespace tofcomp::ipc::socket
