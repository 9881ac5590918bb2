// The low-rate summary of a scanner's compensated ranges for the `ranges` topic: over one period,
// per beam (every beam_step-th) the mean and standard deviation of the compensated range and the
// share of its scans that had one, and per flag the share of all ranges that carried it. A fleet
// dashboard sees a wall move, a beam go blind or the temperature leave the calibration's range
// without receiving 75 scans a second.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <vector>

#include "tofcomp/client.hpp"

namespace tofcomp::bridges::mqtt {

// The most beams a summary carries (the ring's largest scan); with beam_step 1 and 1024 beams the
// payload stays under kMaxRangesPayloadBytes.
inline constexpr std::size_t kMaxSummaryBeams = 1024;
inline constexpr std::size_t kMaxRangesPayloadBytes = 96 * 1024;

class RangeSummary {
 public:
  explicit RangeSummary(int beam_step) : beam_step_(beam_step) {}

  void add(const client::Scan& scan);
  std::uint64_t scans() const { return scans_; }
  // The period's summary as JSON, then starts the next period. Means and standard deviations
  // are rounded to 0.01 mm (the compensation's resolution is far coarser), shares to 0.001.
  nlohmann::ordered_json take();

 private:
  struct BeamSums {
    std::uint64_t count = 0;  // scans with a compensated range
    double sum = 0.0;
    double sum_squares = 0.0;  // of the deviations from `shift`, for a stable variance
    double shift = 0.0;
  };
  int beam_step_;
  std::uint64_t scans_ = 0;
  std::uint64_t ranges_ = 0;  // beams seen over all scans, for the flag shares
  std::uint32_t first_beam_ = 0;
  std::int64_t first_timestamp_ns_ = 0;
  std::int64_t last_timestamp_ns_ = 0;
  std::uint64_t last_sequence_ = 0;
  std::vector<BeamSums> beams_;
  std::vector<std::uint64_t> flag_counts_;
};

}  // namespace tofcomp::bridges::mqtt
