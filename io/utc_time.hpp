// Times as tofcomp writes them for people and files: ISO 8601 in UTC, "2026-11-23T10:48:21.137Z".
// The one formatter of the calibration's provenance, `tofcomp query` and `tofcomp shm-dump`.
#pragma once

#include <cstdint>
#include <string>

namespace tofcomp::io {

inline constexpr int kMaxFractionDigits = 9;  // nanoseconds

// ns since the epoch (CLOCK_REALTIME) as "YYYY-MM-DDTHH:MM:SS[.f...]Z" with fraction_digits
// (0 to 9, clamped) digits of the second, truncated; times before 1970 count back correctly.
std::string utc_timestamp(std::int64_t ns_since_epoch, int fraction_digits);

// Now, to the second.
std::string utc_now();

}  // namespace tofcomp::io
