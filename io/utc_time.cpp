#include "io/utc_time.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>

namespace tofcomp::io {

std::string utc_timestamp(std::int64_t ns_since_epoch, int fraction_digits) {
  constexpr std::int64_t kNsPerSecond = 1'000'000'000;
  std::int64_t seconds = ns_since_epoch / kNsPerSecond;
  std::int64_t ns = ns_since_epoch % kNsPerSecond;
  if (ns < 0) {  // floor, not truncation toward zero, before the epoch
    ns += kNsPerSecond;
    --seconds;
  }
  const auto t = static_cast<std::time_t>(seconds);
  std::tm utc{};
  if (gmtime_r(&t, &utc) == nullptr) return std::to_string(ns_since_epoch) + " ns";
  char text[64];
  int length = std::snprintf(text, sizeof text, "%04d-%02d-%02dT%02d:%02d:%02d", utc.tm_year + 1900,
                             utc.tm_mon + 1, utc.tm_mday, utc.tm_hour, utc.tm_min, utc.tm_sec);
  const int digits = std::clamp(fraction_digits, 0, kMaxFractionDigits);
  if (digits > 0) {
    std::int64_t fraction = ns;
    for (int d = digits; d < kMaxFractionDigits; ++d) fraction /= 10;
    length += std::snprintf(text + length, sizeof text - static_cast<std::size_t>(length),
                            ".%0*lld", digits, static_cast<long long>(fraction));
  }
  return std::string(text, static_cast<std::size_t>(length)) + "Z";
}

std::string utc_now() {
  const auto now = std::chrono::system_clock::now().time_since_epoch();
  return utc_timestamp(std::chrono::duration_cast<std::chrono::nanoseconds>(now).count(), 0);
}

}  // namespace tofcomp::io
