// The scan telegram 0xB0: a u16 header (bits 0-9 the number of values, bits 11-12 the partial
// scan of an interlaced scan, bit 13 set on a partial scan, bits 14-15 the units), the values
// (distance in the low bits, flags in the high bits, split by the measuring mode), and the
// device's status byte. The listing's section on measured values (*verify* the interlace bits).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "hal/lms2xx/commands.hpp"
#include "hal/lms2xx/measuring_mode.hpp"
#include "hal/lms2xx/telegram.hpp"

namespace tofcomp::hal::lms2xx {

inline constexpr int kMaxValuesPerScan = 401;

// The DATA of a scan telegram of `values` values: the u16 header, two bytes a value, the status.
constexpr std::size_t scan_data_bytes(int values) {
  return 2 + 2 * static_cast<std::size_t>(values) + 1;
}

struct ScanTelegram {
  Units units = Units::Millimetre;
  bool partial = false;
  std::uint8_t partial_index = 0;  // 0-3, which turn of an interlaced scan
  std::vector<std::uint16_t> distance_codes;  // flags stripped; reserved codes kept
  std::vector<std::uint8_t> flags;            // the bits above the distance, one per value
  std::uint8_t status = 0;

  // The distance of value i in millimetres (cm codes times 10); only for ValueStatus::Distance.
  double distance_mm(std::size_t i) const;
  bool operator==(const ScanTelegram&) const = default;
};

// The DATA of a 0xB0 telegram (status byte last). Throws core::InvalidInput when a code does
// not fit the mode's distance bits or there are more than kMaxValuesPerScan values.
std::vector<std::uint8_t> encode_scan_data(const ScanTelegram& scan, MeasuringMode mode);
// Decodes the DATA of a 0xB0 telegram. Throws core::InvalidInput naming the byte at fault when
// the count disagrees with the length.
ScanTelegram decode_scan_data(std::span<const std::uint8_t> data, MeasuringMode mode);

}  // namespace tofcomp::hal::lms2xx
