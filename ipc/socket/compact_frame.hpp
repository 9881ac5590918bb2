// The compact form of a scan (docs/protocol.md, "Compact frames"): what a subscription with
// "format": "compact" receives instead of a JSON line, about 6 bytes per beam instead of about
// 230. A frame is a fixed little-endian header (magic, version, sizes, the scan's counters, time
// and temperatures, its beam range) followed by the beams' compensated ranges as float32 and
// their flags as uint16. The first byte (0x89) never starts a JSON line, so a client tells a
// frame from a reply by it. Decoding bounds every length: a frame is untrusted input.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "ipc/compensated_scan.hpp"
#include "ipc/socket/protocol_constants.hpp"
#include "ipc/socket/scan_json.hpp"

namespace tofcomp::ipc::socket {

inline constexpr std::array<unsigned char, 4> kCompactMagic{0x89, 'T', 'C', 'S'};
inline constexpr std::uint16_t kCompactFrameVersion = 1;
inline constexpr std::size_t kCompactHeaderBytes = 128;
inline constexpr std::size_t kCompactBytesPerBeam = 4 + 2;  // float32 range, uint16 flags
// A scan has at most as many beams as beam indices go (0..kMaxBeamIndex).
inline constexpr std::size_t kMaxCompactBeams = std::size_t{kMaxBeamIndex} + 1;
inline constexpr std::size_t kMaxCompactFrameBytes =
    kCompactHeaderBytes + kMaxCompactBeams * kCompactBytesPerBeam;

// The beams of span of the scan as one frame. span must lie within scan.beams.
std::string encode_compact_frame(const ipc::CompensatedScan& scan, BeamSpan span);

// The length of the whole frame that starts with header (its first kCompactHeaderBytes bytes),
// after checking the header alone: magic, version, header size, beam counts and the length
// they imply. Throws core::InvalidInput naming the field and its offset.
std::size_t compact_frame_size(std::string_view header);

// A frame read back: the scan with beam_count beams, of which those of span hold the compensated
// range and flags sent; what a frame does not carry (raw range, window, modes) is NaN or 0.
// Throws core::InvalidInput naming what is wrong when frame is not exactly one valid frame.
ReceivedScan decode_compact_frame(std::string_view frame);

}  // namespace tofcomp::ipc::socket
