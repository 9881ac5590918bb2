// When the rays of an LMS 2xx scan were measured, estimated on the host from when the scan's
// telegram finished arriving (docs/protocol.md "Time" states the estimate and its uncertainty).
//
// Device facts (docs/lms2xx-protocol.md, from SICK's public listing): the mirror turns 75 times a
// second; a scan at 1° is one turn, at 0.5° and 0.25° it interlaces 2 and 4 turns, turn t
// measuring the beams i with i mod turns = t, each turn sweeping the field from its first angle
// up. The device sends the scan telegram once the scan's last ray is measured, and the serial
// line carries 10 bits a byte (start, 8 data, stop). So, back from the last byte's arrival:
//   last ray = arrival − line time of the whole telegram,
//   first ray = last ray − the sweep from beam 0 (first turn) to the last beam of the last turn.
// Beam i's ray comes (i mod n)·T + ⌊i / n⌋·Δ after the first (core/ray_timing.hpp), with n the
// interlaced turns, T the turn period and Δ = T·n·resolution / 360 between consecutive rays of
// one turn.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>

#include "core/ray_timing.hpp"
#include "hal/lms2xx/commands.hpp"

namespace tofcomp::hal::lms2xx {

inline constexpr double kMirrorTurnsPerSecond = 75.0;
inline constexpr double kBitsPerLineByte = 10.0;  // start bit, 8 data bits, stop bit
inline constexpr double kDegreesPerTurn = 360.0;

// Time to carry `bytes` over the line at `baud` (10 bits a byte). baud > 0.
std::chrono::nanoseconds line_transfer_time(std::size_t bytes, unsigned baud);

// From beam 0's ray to the scan's last ray (the last beam the last turn measures).
std::chrono::nanoseconds scan_sweep_duration(const Variant& variant);

// The rays' timing of a scan whose telegram of `telegram_bytes` bytes (the whole frame, STX to
// CRC) ended arriving at `last_byte` over a line at `baud`.
core::RayTiming estimate_ray_timing(std::chrono::system_clock::time_point last_byte,
                                    std::size_t telegram_bytes, unsigned baud,
                                    const Variant& variant);

}  // namespace tofcomp::hal::lms2xx
