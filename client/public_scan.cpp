// Scan conversion: the C API's plain structs filled field by field.
#include "client/public_scan.hpp"

#include <algorithm>
#include <utility>

namespace tofcomp::client_detail {

static_assert(TOFCOMP_MAX_MODES == ipc::kMaxModes);
// The C API's flag bits are the published scan's.
constexpr bool same_bit(int c_flag, ipc::BeamFlag flag) {
  return c_flag == static_cast<int>(flag);
}
static_assert(same_bit(TOFCOMP_FLAG_NO_ECHO, ipc::kBeamNoEcho) &&
              same_bit(TOFCOMP_FLAG_UNCALIBRATED, ipc::kBeamUncalibrated) &&
              same_bit(TOFCOMP_FLAG_TEMPERATURE_STALE, ipc::kBeamTemperatureStale) &&
              same_bit(TOFCOMP_FLAG_WINDOW_RESTARTING, ipc::kBeamWindowRestarting) &&
              same_bit(TOFCOMP_FLAG_CHANGE_DETECTED, ipc::kBeamChangeDetected) &&
              same_bit(TOFCOMP_FLAG_OUTLIER, ipc::kBeamOutlier) &&
              same_bit(TOFCOMP_FLAG_TEMPERATURE_EXTRAPOLATED, ipc::kBeamTemperatureExtrapolated));

Scan public_scan(const ipc::CompensatedScan& scan, ipc::socket::BeamSpan span, std::string json) {
  Scan out;
  out.info.sequence = scan.sequence;
  out.info.device_sequence = scan.device_sequence;
  out.info.timestamp_ns = scan.timestamp_ns;
  out.info.junction_c = scan.junction_c;
  out.info.junction_std_c = scan.junction_std_c;
  out.info.case_c = scan.case_c;
  out.info.start_angle_deg = scan.start_angle_deg;
  out.info.resolution_deg = scan.resolution_deg;
  out.info.calibration_id = scan.calibration_id;
  out.info.beam_count = static_cast<std::uint32_t>(scan.beams.size());
  out.info.first_ray_ns = scan.rays.first_ray_ns;
  out.info.ray_interval_ns = scan.rays.ray_interval_ns;
  out.info.turn_period_ns = scan.rays.turn_period_ns;
  out.info.interlaced_turns = scan.rays.interlaced_turns;
  out.beams.reserve(span.count);
  for (std::size_t i = span.first; i < span.first + span.count; ++i) {
    const ipc::BeamValue& value = scan.beams[i];
    Beam beam{};
    beam.index = static_cast<std::uint32_t>(i);
    beam.flags = value.flags;
    beam.mode_count = value.mode_count;
    beam.most_probable_mode = value.most_probable_mode;
    beam.raw_mm = value.raw_mm;
    beam.compensated_mm = value.compensated_mm;
    beam.window_mm = value.window_mm;
    beam.window_std_mm = value.window_std_mm;
    std::copy(value.mode_posterior.begin(), value.mode_posterior.end(), beam.mode_posterior);
    out.beams.push_back(beam);
  }
  out.json = std::move(json);
  return out;
}

}  // namespace tofcomp::client_detail
