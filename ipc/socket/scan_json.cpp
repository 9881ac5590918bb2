// The scan encoder: numbers in their shortest exact form (std::to_chars), non-finite as null.
#include "ipc/socket/scan_json.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <string_view>
#include <system_error>

#include "core/error.hpp"
#include "core/ray_timing.hpp"

namespace tofcomp::ipc::socket {

namespace {

// Appends JSON text to a string; keys and names are the encoder's own (no escaping needed).
class JsonText {
 public:
  explicit JsonText(std::string& out) : out_(out) {}

  void key(std::string_view name) {
    separate();
    out_ += '"';
    out_ += name;
    out_ += "\":";
    fresh_ = true;
  }
  void open(char bracket) {
    separate();
    out_ += bracket;
    fresh_ = true;
  }
  void close(char bracket) {
    out_ += bracket;
    fresh_ = false;
  }
  void name(std::string_view text) {
    separate();
    out_ += '"';
    out_ += text;
    out_ += '"';
  }
  void number(double value) {
    separate();
    if (!std::isfinite(value)) {
      out_ += "null";
      return;
    }
    append_chars(value);
  }
  // A float as the shortest decimal that reads back as that float (0.1f is "0.1").
  void number(float value) {
    separate();
    if (!std::isfinite(value)) {
      out_ += "null";
      return;
    }
    append_chars(value);
  }
  template <typename Integer>
  void integer(Integer value) {
    separate();
    append_chars(value);
  }

 private:
  std::string& out_;
  bool fresh_ = true;  // nothing written yet in the current object or array, or after a key

  void separate() {
    if (!fresh_) out_ += ',';
    fresh_ = false;
  }
  template <typename T>
  void append_chars(T value) {
    std::array<char, 32> buffer;
    const auto [end, ec] = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
    if (ec != std::errc()) throw core::Error("scan encoder: a number did not fit 32 characters");
    out_.append(buffer.data(), end);
  }
};

void encode_beam(JsonText& text, const ipc::BeamValue& beam, std::size_t index) {
  text.open('{');
  text.key("index");
  text.integer(index);
  text.key("raw_mm");
  text.number(beam.raw_mm);
  text.key("compensated_mm");
  text.number(beam.compensated_mm);
  text.key("window_mm");
  text.number(beam.window_mm);
  text.key("window_std_mm");
  text.number(beam.window_std_mm);
  text.key("flags");
  text.integer(beam.flags);
  text.key("flag_names");
  text.open('[');
  for (const auto& name : beam_flag_names(beam.flags)) text.name(name);
  text.close(']');
  text.key("mode_count");
  text.integer(static_cast<unsigned>(beam.mode_count));
  text.key("most_probable_mode");
  text.integer(static_cast<unsigned>(beam.most_probable_mode));
  text.key("mode_posterior");
  text.open('[');
  const std::size_t modes = std::min<std::size_t>(beam.mode_count, ipc::kMaxModes);
  for (std::size_t m = 0; m < modes; ++m) text.number(beam.mode_posterior[m]);
  text.close(']');
  text.close('}');
}

// "rays": when the scan's rays were measured (core/ray_timing.hpp), null when unknown.
void encode_rays(JsonText& text, const core::RayTiming& rays) {
  text.key("rays");
  if (!rays.known()) {
    text.number(std::numeric_limits<double>::quiet_NaN());  // null
    return;
  }
  text.open('{');
  text.key("first_ray_ns");
  text.integer(rays.first_ray_ns);
  text.key("ray_interval_ns");
  text.number(rays.ray_interval_ns);
  text.key("turn_period_ns");
  text.number(rays.turn_period_ns);
  text.key("interlaced_turns");
  text.integer(rays.interlaced_turns);
  text.close('}');
}

}  // namespace

BeamSpan beams_exactly(const std::optional<BeamRange>& wanted, std::size_t beam_count) {
  if (!wanted) return {0, beam_count};
  if (wanted->last >= beam_count) {
    throw ProtocolError(ErrorCode::BadRange,
                        "beams: [" + std::to_string(wanted->first) + ", " +
                            std::to_string(wanted->last) + "] reaches beyond the scan, which has " +
                            std::to_string(beam_count) + " beams" +
                            (beam_count > 0 ? " (0.." + std::to_string(beam_count - 1) + ")" : ""));
  }
  return {wanted->first, std::size_t{wanted->last} - wanted->first + 1};
}

BeamSpan beams_clipped(const std::optional<BeamRange>& wanted, std::size_t beam_count) {
  if (!wanted) return {0, beam_count};
  if (wanted->first >= beam_count) return {wanted->first, 0};
  const std::size_t end = std::min<std::size_t>(std::size_t{wanted->last} + 1, beam_count);
  return {wanted->first, end - wanted->first};
}

std::string encode_scan(const ipc::CompensatedScan& scan, BeamSpan span) {
  if (span.count > 0 &&
      (span.first >= scan.beams.size() || span.count > scan.beams.size() - span.first)) {
    throw core::InvalidInput("encode_scan: beams " + std::to_string(span.first) + " + " +
                             std::to_string(span.count) + " lie outside the scan's " +
                             std::to_string(scan.beams.size()) + " beams");
  }
  std::string out;
  out.reserve(400 + 200 * span.count);
  JsonText json(out);
  json.open('{');
  json.key("sequence");
  json.integer(scan.sequence);
  json.key("device_sequence");
  json.integer(scan.device_sequence);
  json.key("timestamp_ns");
  json.integer(scan.timestamp_ns);
  encode_rays(json, scan.rays);
  json.key("junction_c");
  json.number(scan.junction_c);
  json.key("junction_std_c");
  json.number(scan.junction_std_c);
  json.key("case_c");
  json.number(scan.case_c);
  json.key("start_angle_deg");
  json.number(scan.start_angle_deg);
  json.key("resolution_deg");
  json.number(scan.resolution_deg);
  json.key("calibration_id");
  json.integer(scan.calibration_id);
  json.key("beam_count");
  json.integer(scan.beams.size());
  json.key("first_beam");
  json.integer(span.first);
  json.key("beams");
  json.open('[');
  for (std::size_t i = span.first; i < span.first + span.count; ++i) {
    encode_beam(json, scan.beams[i], i);
  }
  json.close(']');
  json.close('}');
  return out;
}

namespace {

// A number of the object, null (a value that does not exist) as NaN.
double number_or_nan(const nlohmann::json& object, const char* key) {
  const nlohmann::json& value = object.at(key);
  return value.is_null() ? std::numeric_limits<double>::quiet_NaN() : value.get<double>();
}

// "rays" of a scan object; absent (an older daemon) or null: unknown.
core::RayTiming decode_rays(const nlohmann::json& scan) {
  core::RayTiming rays;
  const auto found = scan.find("rays");
  if (found == scan.end() || found->is_null()) return rays;
  rays.first_ray_ns = found->at("first_ray_ns").get<std::int64_t>();
  rays.ray_interval_ns = found->at("ray_interval_ns").get<double>();
  rays.turn_period_ns = found->at("turn_period_ns").get<double>();
  rays.interlaced_turns = found->at("interlaced_turns").get<std::uint32_t>();
  if (rays.interlaced_turns > core::kMaxInterlacedTurns) {
    throw core::InvalidInput("rays.interlaced_turns " + std::to_string(rays.interlaced_turns) +
                             " is more than " + std::to_string(core::kMaxInterlacedTurns));
  }
  return rays;
}

ipc::BeamValue decode_beam(const nlohmann::json& object) {
  ipc::BeamValue beam;
  beam.raw_mm = number_or_nan(object, "raw_mm");
  beam.compensated_mm = number_or_nan(object, "compensated_mm");
  beam.window_mm = number_or_nan(object, "window_mm");
  beam.window_std_mm = number_or_nan(object, "window_std_mm");
  beam.flags = object.at("flags").get<std::uint16_t>();
  beam.mode_count = object.at("mode_count").get<std::uint8_t>();
  beam.most_probable_mode = object.at("most_probable_mode").get<std::uint8_t>();
  const nlohmann::json& posterior = object.at("mode_posterior");
  for (std::size_t m = 0; m < posterior.size() && m < ipc::kMaxModes; ++m) {
    beam.mode_posterior[m] = posterior[m].is_null() ? std::numeric_limits<float>::quiet_NaN()
                                                    : posterior[m].get<float>();
  }
  return beam;
}

}  // namespace

ReceivedScan decode_scan(const nlohmann::json& object) {
  try {
    ReceivedScan r;
    ipc::CompensatedScan& s = r.scan;
    s.sequence = object.at("sequence").get<std::uint64_t>();
    s.device_sequence = object.at("device_sequence").get<std::uint64_t>();
    s.timestamp_ns = object.at("timestamp_ns").get<std::int64_t>();
    s.rays = decode_rays(object);
    s.junction_c = number_or_nan(object, "junction_c");
    s.junction_std_c = number_or_nan(object, "junction_std_c");
    s.case_c = number_or_nan(object, "case_c");
    s.start_angle_deg = number_or_nan(object, "start_angle_deg");
    s.resolution_deg = number_or_nan(object, "resolution_deg");
    s.calibration_id = object.at("calibration_id").get<std::uint32_t>();
    s.beams.resize(object.at("beam_count").get<std::size_t>());
    const nlohmann::json& beams = object.at("beams");
    r.span = {object.at("first_beam").get<std::size_t>(), beams.size()};
    if (r.span.count > 0 &&
        (r.span.first >= s.beams.size() || r.span.count > s.beams.size() - r.span.first)) {
      throw core::InvalidInput("beams " + std::to_string(r.span.first) + " + " +
                               std::to_string(r.span.count) + " lie outside its " +
                               std::to_string(s.beams.size()) + " beams");
    }
    for (std::size_t i = 0; i < r.span.count; ++i) {
      s.beams[r.span.first + i] = decode_beam(beams[i]);
    }
    return r;
  } catch (const nlohmann::json::exception& e) {
    throw core::InvalidInput(std::string("a scan object of the socket protocol: ") + e.what());
  } catch (const core::InvalidInput& e) {
    throw core::InvalidInput(std::string("a scan object of the socket protocol: ") + e.what());
  }
}

}  // namespace tofcomp::ipc::socket
