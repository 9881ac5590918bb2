// What tofcompd publishes for each scan, to the shared-memory ring (docs/shm-ring.md) and the
// Unix socket (docs/protocol.md): per beam the raw range, the compensated range
// y − H(t̂^j)θ̂ − μ_î (Eq. 8 with the most probable mode î), the sliding-window EM estimate d̂
// (§6) with its standard deviation, the mode posteriors of this range, and flags.
// Distances are in millimetres. A value that does not exist (no echo, no calibration, a window
// still filling) is NaN in memory with the flag that says why; the publishers never write a
// NaN anywhere a reader would take it for a number (the ring keeps the flag, JSON writes null).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/ray_timing.hpp"

namespace tofcomp::ipc {

inline constexpr int kMaxModes = 4;  // lasing modes carried per beam

// Per-beam flags (bit values are part of the ring layout and the socket protocol).
enum BeamFlag : std::uint16_t {
  kBeamNoEcho = 1u << 0,            // the device reported no range (beyond range, dazzle, ...)
  kBeamUncalibrated = 1u << 1,      // no calibration loaded: compensated and window are NaN
  kBeamTemperatureStale = 1u << 2,  // no fresh case reading: the junction estimate is predicted
  kBeamWindowRestarting = 1u << 3,  // the window has fewer than its minimum samples
  kBeamChangeDetected = 1u << 4,    // this range restarted the window (the distance moved)
  kBeamOutlier = 1u << 5,  // the calibration's outlier component takes this range (P > 0.5)
  // t̂^j lies outside the junction temperatures the calibration was trained on: the bias is held
  // at its value at the nearer end of that range (core/measurement_model.hpp), not extrapolated
  kBeamTemperatureExtrapolated = 1u << 6,
};

// The flags' names, by bit (the socket's flag_names, shm-dump's and replay's flags column).
inline constexpr std::array<std::string_view, 7> kBeamFlagNames{
    "no_echo",         "uncalibrated", "temperature_stale",       "window_restarting",
    "change_detected", "outlier",      "temperature_extrapolated"};

// The names of the set bits, lowest bit first; "bitN" for a bit without a name.
inline std::vector<std::string> beam_flag_names(std::uint16_t flags) {
  constexpr unsigned kFlagBits = 16;
  std::vector<std::string> names;
  for (unsigned bit = 0; bit < kFlagBits; ++bit) {
    if ((flags & (1u << bit)) == 0) continue;
    names.emplace_back(bit < kBeamFlagNames.size() ? std::string(kBeamFlagNames[bit])
                                                   : "bit" + std::to_string(bit));
  }
  return names;
}

struct BeamValue {
  double raw_mm = 0.0;
  double compensated_mm = 0.0;                    // NaN when uncalibrated or no echo
  double window_mm = 0.0;                         // d̂ of the beam's window; NaN while none
  double window_std_mm = 0.0;                     // its standard deviation; NaN while none
  std::array<float, kMaxModes> mode_posterior{};  // P(mode i | this range); unused modes 0
  std::uint16_t flags = 0;
  std::uint8_t mode_count = 0;  // modes of the calibration (0 when uncalibrated)
  std::uint8_t most_probable_mode = 0;
};

struct CompensatedScan {
  std::uint64_t sequence = 0;         // the daemon's scan counter, from 0, no gaps
  std::uint64_t device_sequence = 0;  // the host driver's scan counter
  std::int64_t timestamp_ns = 0;      // host receive time, CLOCK_REALTIME, ns since the epoch
  // When its rays were measured: beam 0's ray and the sweep (estimated back from the arrival,
  // docs/protocol.md "Time"); unknown (interlaced_turns 0) for a recording's scans.
  core::RayTiming rays;
  double junction_c = 0.0;            // t̂^j at the scan (Kalman filter, §3.3); NaN if none
  double junction_std_c = 0.0;
  double case_c = 0.0;               // latest accepted case reading; NaN if none
  double start_angle_deg = 0.0;      // angle of beam 0
  double resolution_deg = 0.0;       // angle step between beams
  std::uint32_t calibration_id = 0;  // increments at each calibration swap; 0 = none
  std::vector<BeamValue> beams;
};

}  // namespace tofcomp::ipc
