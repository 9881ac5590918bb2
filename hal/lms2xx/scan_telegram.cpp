#include "hal/lms2xx/scan_telegram.hpp"

#include <string>

#include "core/error.hpp"

namespace tofcomp::hal::lms2xx {

namespace {
constexpr std::uint16_t kCountMask = 0x03ff;
constexpr int kPartialIndexShift = 11;
constexpr std::uint16_t kPartialFlag = 1u << 13;
constexpr int kUnitsShift = 14;
}  // namespace

double ScanTelegram::distance_mm(std::size_t i) const {
  const double unit = units == Units::Millimetre ? 1.0 : 10.0;
  return unit * distance_codes.at(i);
}

std::vector<std::uint8_t> encode_scan_data(const ScanTelegram& scan, MeasuringMode mode) {
  const std::size_t n = scan.distance_codes.size();
  if (n > static_cast<std::size_t>(kMaxValuesPerScan) || scan.flags.size() != n ||
      scan.partial_index > 3) {
    throw core::InvalidInput("scan telegram: " + std::to_string(n) + " values with " +
                             std::to_string(scan.flags.size()) + " flags and partial index " +
                             std::to_string(scan.partial_index) + " cannot be encoded");
  }
  const int bits = distance_bits(mode);
  std::vector<std::uint8_t> data;
  data.reserve(scan_data_bytes(static_cast<int>(n)));
  std::uint16_t header = static_cast<std::uint16_t>(n);
  header |= static_cast<std::uint16_t>(scan.partial_index << kPartialIndexShift);
  if (scan.partial) header |= kPartialFlag;
  header |= static_cast<std::uint16_t>(static_cast<unsigned>(scan.units) << kUnitsShift);
  put_u16(data, header);
  for (std::size_t i = 0; i < n; ++i) {
    if (scan.distance_codes[i] >> bits != 0 || scan.flags[i] >> (16 - bits) != 0) {
      throw core::InvalidInput("scan telegram: value " + std::to_string(i) + " (code " +
                               std::to_string(scan.distance_codes[i]) + ") does not fit " +
                               std::to_string(bits) + " distance bits");
    }
    put_u16(data, static_cast<std::uint16_t>(scan.distance_codes[i] | (scan.flags[i] << bits)));
  }
  data.push_back(scan.status);
  return data;
}

ScanTelegram decode_scan_data(std::span<const std::uint8_t> data, MeasuringMode mode) {
  if (data.size() < 3) {
    throw core::InvalidInput("scan telegram: " + std::to_string(data.size()) +
                             " bytes of data, too short for the header and status");
  }
  const std::uint16_t header = get_u16(data, 0);
  const std::size_t n = header & kCountMask;
  if (n > static_cast<std::size_t>(kMaxValuesPerScan)) {
    throw core::InvalidInput("scan telegram: header announces " + std::to_string(n) +
                             " values, more than " + std::to_string(kMaxValuesPerScan));
  }
  // Values, then the status byte; a real-time scan index (2 bytes) may precede the status.
  const std::size_t expected = scan_data_bytes(static_cast<int>(n));
  if (data.size() != expected && data.size() != expected + 2) {
    throw core::InvalidInput("scan telegram: header announces " + std::to_string(n) +
                             " values (" + std::to_string(expected) + " bytes) but the data has " +
                             std::to_string(data.size()) + " bytes");
  }
  const unsigned units = header >> kUnitsShift;
  if (units > 1) {
    throw core::InvalidInput("scan telegram: header bits 14-15 hold units code " +
                             std::to_string(units) + ", expected 0 (cm) or 1 (mm)");
  }
  ScanTelegram scan;
  scan.units = static_cast<Units>(units);
  scan.partial = (header & kPartialFlag) != 0;
  scan.partial_index = static_cast<std::uint8_t>((header >> kPartialIndexShift) & 0x3);
  const int bits = distance_bits(mode);
  const std::uint16_t mask = static_cast<std::uint16_t>((1u << bits) - 1u);
  scan.distance_codes.resize(n);
  scan.flags.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint16_t word = get_u16(data, 2 + 2 * i);
    scan.distance_codes[i] = word & mask;
    scan.flags[i] = static_cast<std::uint8_t>(word >> bits);
  }
  scan.status = data.back();
  return scan;
}

}  // namespace tofcomp::hal::lms2xx
