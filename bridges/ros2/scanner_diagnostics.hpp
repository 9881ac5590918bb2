// The scanner's health as the content of a ROS 2 diagnostic_msgs/msg/DiagnosticStatus: the
// daemon's `status` (link, state, calibration and its extension, the device) with the latest
// scan's junction temperature and the share of flagged beams over the scans since the last
// report. Key names and levels: docs/integration.md, "ROS 2".
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "tofcomp/client.hpp"

namespace tofcomp::bridges::ros2 {

// DiagnosticStatus's levels (diagnostic_msgs/msg/DiagnosticStatus.msg).
enum class DiagnosticLevel : std::uint8_t { Ok = 0, Warn = 1, Error = 2, Stale = 3 };

// The flags that say a beam's compensated range is missing or less trustworthy for a reason of
// the scanner's or the compensation's: no calibration, a stale case temperature, an outlier, a
// junction temperature beyond the trained ones. No echo is the scene's (nothing within range:
// REP 117's +Inf), counted apart; the window's flags (restarting, change detected) concern d̂,
// not the range published.
inline constexpr std::uint16_t kRangeFlags =
    TOFCOMP_FLAG_UNCALIBRATED | TOFCOMP_FLAG_TEMPERATURE_STALE | TOFCOMP_FLAG_OUTLIER |
    TOFCOMP_FLAG_TEMPERATURE_EXTRAPOLATED;
// Above this share of flagged beams over a report's scans, the level is WARN.
inline constexpr double kWarnFlaggedShare = 0.25;

// The beams of the scans since the last report: how many carried a range flag, how many no echo.
class FlaggedBeams {
 public:
  void add(const client::Scan& scan);
  void clear() { *this = FlaggedBeams(); }
  std::uint64_t scans() const { return scans_; }
  std::uint64_t beams() const { return beams_; }
  std::uint64_t flagged() const { return flagged_; }
  std::uint64_t no_echo() const { return no_echo_; }
  std::uint64_t first_sequence() const { return first_sequence_; }
  std::uint64_t last_sequence() const { return last_sequence_; }
  double share() const;  // flagged / beams; 0 without beams

 private:
  std::uint64_t scans_ = 0, beams_ = 0, flagged_ = 0, no_echo_ = 0;
  std::uint64_t first_sequence_ = 0, last_sequence_ = 0;
};

struct DiagnosticValues {
  DiagnosticLevel level = DiagnosticLevel::Ok;
  std::string name;
  std::string message;
  std::string hardware_id;
  std::vector<std::pair<std::string, std::string>> values;  // key, value
};

// The report's name, "tofcompd: <socket>", which tells two scanners' reports apart.
std::string diagnostic_name(const std::string& socket_path);

// From the daemon's `status` object (docs/protocol.md), the latest scan received (none yet:
// nullopt) and the beams since the last report. Levels: ERROR when the link is not streaming;
// STALE when no scan came since the last report; WARN without a calibration or above
// kWarnFlaggedShare; OK otherwise. Throws nlohmann::json::exception when status lacks a member.
DiagnosticValues scanner_diagnostics(const nlohmann::json& status,
                                     const std::optional<client::ScanInfo>& latest,
                                     const FlaggedBeams& beams, const std::string& socket_path);

// The report while tofcompd cannot be reached: ERROR, with the reason.
DiagnosticValues unreachable_diagnostics(const std::string& socket_path, const std::string& why);

// A number as the shortest text that reads back to the same double ("24.81", "nan").
std::string number_text(double value);

}  // namespace tofcomp::bridges::ros2
