// SICK's CRC-16 of the LMS 2xx telegram (the listing's section on the telegram frame): a
// polynomial 0x8005 checksum over pairs of bytes, initial value 0. It is not CRC-16/ARC; the
// known-answer tests in tests/hal/lms2xx/crc16_test.cpp pin it to telegrams of the listing.
#pragma once

#include <cstdint>
#include <span>

namespace tofcomp::hal::lms2xx {

// The checksum of `bytes` (every byte of a telegram from STX to the end of its data).
std::uint16_t sick_crc16(std::span<const std::uint8_t> bytes);

}  // namespace tofcomp::hal::lms2xx
