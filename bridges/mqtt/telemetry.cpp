// The telemetry topics' payloads.
#include "bridges/mqtt/telemetry.hpp"

#include <array>
#include <chrono>
#include <cmath>
#include <string_view>

namespace tofcomp::bridges::mqtt {

namespace {

using Json = nlohmann::ordered_json;

// A NaN (a value that does not exist) is null in JSON, never a number.
Json number_or_null(double value) {
  return std::isfinite(value) ? Json(value) : Json(nullptr);
}

std::string dump(const Json& payload) {
  return payload.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

// The flags worth a finding, with what each means for the scanner's ranges.
struct FlagFinding {
  std::string_view flag;
  std::string_view meaning;
};
constexpr std::array<FlagFinding, 5> kFlagFindings{{
    {"uncalibrated", "no calibration loaded: ranges are not compensated"},
    {"temperature_stale", "no fresh case reading: the junction estimate is predicted"},
    {"temperature_extrapolated",
     "junction outside the calibration's trained temperatures: recalibrate over a wider range"},
    {"outlier", "ranges taken by the calibration's outlier component"},
    {"no_echo", "beams without a range (beyond range, dazzled, blocked)"},
}};

}  // namespace

std::int64_t realtime_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

std::string status_payload(const nlohmann::json& status, const std::string& error) {
  Json out;
  out["published_ns"] = realtime_ns();
  out["tofcompd"] = status;
  if (!error.empty()) out["error"] = error;
  return dump(out);
}

std::string calibration_payload(const nlohmann::json& status) {
  Json out;
  out["published_ns"] = realtime_ns();
  out["calibration"] = status.value("calibration", nlohmann::json(nullptr));
  return dump(out);
}

std::string junction_payload(const client::Scan& scan) {
  Json out;
  out["sequence"] = scan.info.sequence;
  out["timestamp_ns"] = scan.info.timestamp_ns;
  out["junction_c"] = number_or_null(scan.info.junction_c);
  out["junction_std_c"] = number_or_null(scan.info.junction_std_c);
  out["case_c"] = number_or_null(scan.info.case_c);
  out["calibration_id"] = scan.info.calibration_id;
  out["published_ns"] = realtime_ns();
  return dump(out);
}

std::string diagnosis_payload(const nlohmann::json& status, const nlohmann::json& flag_share) {
  Json out;
  out["published_ns"] = realtime_ns();
  Json findings = Json::array();
  if (!status.is_object()) {
    findings.push_back({{"what", "tofcompd"}, {"meaning", "tofcompd cannot be reached"}});
  } else {
    const nlohmann::json calibration = status.value("calibration", nlohmann::json::object());
    out["model_extension"] = calibration.value("extension", nlohmann::json(nullptr));
    out["recalibration"] = status.value("recalibration", "");
    out["case_sensor"] = status.value("case_sensor", nlohmann::json(nullptr));
    out["link"] = status.value("link", "");
    const std::string recalibration = status.value("recalibration", "");
    if (recalibration.rfind("rejected", 0) == 0 || recalibration.rfind("failed", 0) == 0) {
      findings.push_back({{"what", "recalibration"}, {"meaning", recalibration}});
    }
    const nlohmann::json sensor = status.value("case_sensor", nlohmann::json::object());
    if (sensor.is_object() && sensor.value("state", "valid") != "valid") {
      findings.push_back({{"what", "case_sensor"}, {"meaning", sensor.value("state", "")}});
    }
  }
  if (flag_share.is_object()) {
    for (const FlagFinding& finding : kFlagFindings) {
      const std::string flag(finding.flag);
      const double share = flag_share.value(flag, 0.0);
      if (share > 0.0) {
        findings.push_back({{"what", flag}, {"share", share}, {"meaning", finding.meaning}});
      }
    }
  }
  out["flag_share"] = flag_share;
  out["findings"] = std::move(findings);
  return dump(out);
}

}  // namespace tofcomp::bridges::mqtt
