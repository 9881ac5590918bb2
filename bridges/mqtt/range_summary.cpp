// The ranges summary: sums per beam over a period, then their moments as JSON.
#include "bridges/mqtt/range_summary.hpp"

#include <cmath>

#include "ipc/compensated_scan.hpp"

namespace tofcomp::bridges::mqtt {

namespace {

// To 1/scale: the double nearest the decimal, which JSON then writes in few digits.
double rounded(double value, double scale) {
  return std::round(value * scale) / scale;
}

constexpr double kMillimetreScale = 100.0;  // 0.01 mm
constexpr double kShareScale = 1000.0;      // 0.001

}  // namespace

void RangeSummary::add(const client::Scan& scan) {
  if (scan.beams.empty()) return;
  const auto step = static_cast<std::size_t>(beam_step_);
  const std::size_t kept = std::min(kMaxSummaryBeams, (scan.beams.size() + step - 1) / step);
  if (scans_ == 0 || beams_.size() != kept || first_beam_ != scan.beams.front().index) {
    // The first scan of a period, or the scan's beams changed (another field of view): start
    // over from this scan.
    beams_.assign(kept, BeamSums{});
    flag_counts_.assign(ipc::kBeamFlagNames.size(), 0);
    scans_ = 0;
    ranges_ = 0;
    first_beam_ = scan.beams.front().index;
    first_timestamp_ns_ = scan.info.timestamp_ns;
  }
  ++scans_;
  last_timestamp_ns_ = scan.info.timestamp_ns;
  last_sequence_ = scan.info.sequence;
  for (const client::Beam& beam : scan.beams) {
    ++ranges_;
    for (std::size_t bit = 0; bit < flag_counts_.size(); ++bit) {
      if ((beam.flags & (1u << bit)) != 0) ++flag_counts_[bit];
    }
  }
  for (std::size_t i = 0; i < kept; ++i) {
    const double value = scan.beams[i * step].compensated_mm;
    if (!std::isfinite(value)) continue;
    BeamSums& sums = beams_[i];
    if (sums.count == 0) sums.shift = value;
    const double deviation = value - sums.shift;
    ++sums.count;
    sums.sum += deviation;
    sums.sum_squares += deviation * deviation;
  }
}

nlohmann::ordered_json RangeSummary::take() {
  nlohmann::ordered_json out;
  out["scans"] = scans_;
  out["from_ns"] = first_timestamp_ns_;
  out["to_ns"] = last_timestamp_ns_;
  out["last_sequence"] = last_sequence_;
  out["first_beam"] = first_beam_;
  out["beam_step"] = beam_step_;
  nlohmann::ordered_json mean = nlohmann::ordered_json::array();
  nlohmann::ordered_json deviation = nlohmann::ordered_json::array();
  nlohmann::ordered_json valid = nlohmann::ordered_json::array();
  for (const BeamSums& sums : beams_) {
    if (sums.count == 0) {
      mean.push_back(nullptr);
      deviation.push_back(nullptr);
    } else {
      const double n = static_cast<double>(sums.count);
      const double average = sums.sum / n;
      const double variance = std::max(0.0, sums.sum_squares / n - average * average);
      mean.push_back(rounded(sums.shift + average, kMillimetreScale));
      deviation.push_back(rounded(std::sqrt(variance), kMillimetreScale));
    }
    valid.push_back(scans_ == 0 ? 0.0
                                : rounded(static_cast<double>(sums.count) /
                                              static_cast<double>(scans_),
                                          kShareScale));
  }
  out["mean_mm"] = std::move(mean);
  out["std_mm"] = std::move(deviation);
  out["valid_share"] = std::move(valid);
  nlohmann::ordered_json flags = nlohmann::ordered_json::object();
  for (std::size_t bit = 0; bit < flag_counts_.size(); ++bit) {
    flags[std::string(ipc::kBeamFlagNames[bit])] =
        ranges_ == 0 ? 0.0
                     : rounded(static_cast<double>(flag_counts_[bit]) /
                                   static_cast<double>(ranges_),
                               kShareScale);
  }
  out["flag_share"] = std::move(flags);
  scans_ = 0;
  return out;
}

}  // namespace tofcomp::bridges::mqtt
