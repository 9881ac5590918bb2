#include "bridges/ros2/scanner_diagnostics.hpp"

#include <array>
#include <charconv>
#include <cmath>

namespace tofcomp::bridges::ros2 {

namespace {

// tofcompd's link state while scans flow (docs/lms2xx-link.md): "streaming: ...".
constexpr std::string_view kStreamingPrefix = "streaming";

std::string text_or_none(const nlohmann::json& value) {
  return value.is_null() ? "none" : value.get<std::string>();
}

}  // namespace

void FlaggedBeams::add(const client::Scan& scan) {
  if (scans_ == 0) first_sequence_ = scan.info.sequence;
  last_sequence_ = scan.info.sequence;
  ++scans_;
  beams_ += scan.beams.size();
  for (const client::Beam& beam : scan.beams) {
    if ((beam.flags & kRangeFlags) != 0) ++flagged_;
    if ((beam.flags & TOFCOMP_FLAG_NO_ECHO) != 0) ++no_echo_;
  }
}

double FlaggedBeams::share() const {
  return beams_ == 0 ? 0.0 : static_cast<double>(flagged_) / static_cast<double>(beams_);
}

std::string number_text(double value) {
  if (std::isnan(value)) return "nan";
  std::array<char, 32> buffer{};
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  return std::string(buffer.data(), result.ptr);
}

std::string diagnostic_name(const std::string& socket_path) { return "tofcompd: " + socket_path; }

DiagnosticValues scanner_diagnostics(const nlohmann::json& status,
                                     const std::optional<client::ScanInfo>& latest,
                                     const FlaggedBeams& beams, const std::string& socket_path) {
  DiagnosticValues out;
  out.name = diagnostic_name(socket_path);
  out.hardware_id = status.at("device").get<std::string>();
  const std::string link = status.at("link").get<std::string>();
  const std::string state = status.at("state").get<std::string>();
  const nlohmann::json& calibration = status.at("calibration");
  const auto calibration_id = calibration.at("id").get<std::uint32_t>();
  out.message = state;
  if (link.rfind(kStreamingPrefix, 0) != 0) {
    out.level = DiagnosticLevel::Error;
    out.message = "link: " + link;
  } else if (beams.scans() == 0) {
    out.level = DiagnosticLevel::Stale;
    out.message = "no scan since the last report";
  } else if (calibration_id == 0) {
    out.level = DiagnosticLevel::Warn;
    out.message = "no calibration: ranges are not compensated";
  } else if (beams.share() > kWarnFlaggedShare) {
    out.level = DiagnosticLevel::Warn;
    out.message = "flagged beams: " + number_text(beams.share());
  }
  const double nan = std::nan("");
  auto& v = out.values;
  v.emplace_back("junction temperature (°C)", number_text(latest ? latest->junction_c : nan));
  v.emplace_back("junction temperature std (°C)",
                 number_text(latest ? latest->junction_std_c : nan));
  v.emplace_back("case temperature (°C)", number_text(latest ? latest->case_c : nan));
  v.emplace_back("scan", latest ? std::to_string(latest->sequence) : "none");
  v.emplace_back("calibration id", std::to_string(calibration_id));
  v.emplace_back("calibration extension",
                 text_or_none(calibration.value("extension", nlohmann::json())));
  v.emplace_back("link", link);
  v.emplace_back("state", state);
  v.emplace_back("flagged beams (share)", number_text(beams.share()));
  v.emplace_back("flagged beams", std::to_string(beams.flagged()));
  v.emplace_back("beams without echo", std::to_string(beams.no_echo()));
  v.emplace_back("beams", std::to_string(beams.beams()));
  v.emplace_back("scans", std::to_string(beams.scans()));
  v.emplace_back("first scan", beams.scans() ? std::to_string(beams.first_sequence()) : "none");
  v.emplace_back("last scan", beams.scans() ? std::to_string(beams.last_sequence()) : "none");
  return out;
}

DiagnosticValues unreachable_diagnostics(const std::string& socket_path, const std::string& why) {
  DiagnosticValues out;
  out.level = DiagnosticLevel::Error;
  out.name = diagnostic_name(socket_path);
  out.message = "tofcompd unreachable: " + why;
  return out;
}

}  // namespace tofcomp::bridges::ros2
