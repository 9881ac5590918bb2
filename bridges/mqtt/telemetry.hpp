// The payloads of the telemetry topics, as JSON text: each carries published_ns (the bridge's
// CLOCK_REALTIME when it was made) beside what tofcompd said, so that a subscriber can tell how
// old it is and measure the path's latency against a scan's timestamp_ns.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "tofcomp/client.hpp"

namespace tofcomp::bridges::mqtt {

// Now, CLOCK_REALTIME, ns since the epoch.
std::int64_t realtime_ns();

// `status`: tofcompd's status object as it answered (docs/protocol.md, "status"), or, when it
// cannot be reached, null with the reason in "error".
std::string status_payload(const nlohmann::json& status, const std::string& error);

// `calibration`: the calibration in use (status.calibration: id, source, extension).
std::string calibration_payload(const nlohmann::json& status);

// `junction`: one scan's junction temperature estimate t̂ʲ with its standard deviation and the
// case reading, with the scan's sequence and timestamp_ns.
std::string junction_payload(const client::Scan& scan);

// `diagnosis`: the findings a fleet operator acts on, from tofcompd's status (the calibration's
// model extension, the recalibration's verdict, the case sensor, the link) and the flag shares of
// the last ranges period: each finding names what and how much.
std::string diagnosis_payload(const nlohmann::json& status, const nlohmann::json& flag_share);

}  // namespace tofcomp::bridges::mqtt
