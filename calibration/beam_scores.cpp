#include "calibration/beam_scores.hpp"

#include <algorithm>
#include <set>

#include "calibration/junction_estimate.hpp"
#include "calibration/measured_data_reader.hpp"
#include "calibration/still_surfaces.hpp"
#include "core/error.hpp"

namespace tofcomp::calibration {

std::vector<int> beams_with_ranges(const io::MeasurementTable& table) {
  std::set<int> beams;
  for (const io::MeasurementRow& row : table.rows) {
    if (row.range_mm) beams.insert(row.beam.value_or(0));
  }
  return {beams.begin(), beams.end()};
}

BeamScores score_beams(const io::MeasurementTable& table, const std::string& source,
                       const core::Calibration& calibration, std::optional<int> beam,
                       const std::vector<Eigen::Index>& windows, Eigen::Index stride,
                       const std::function<void(double)>& progress,
                       const core::MeasurementModel* band) {
  std::vector<int> beams = beams_with_ranges(table);
  if (beam) {
    if (std::find(beams.begin(), beams.end(), *beam) == beams.end()) {
      throw core::InvalidInput(source + ": beam " + std::to_string(*beam) + " holds no range");
    }
    beams = {*beam};
  }
  BeamScores out;
  out.still_gate_mm = still_gate_mm(calibration.model.mixture);
  core::StillEpisodeOptions still;
  still.gate_mm = out.still_gate_mm;
  RecordJunctions junctions(calibration.thermal, calibration.kalman_noise, calibration.ambient_c);
  for (std::size_t b = 0; b < beams.size(); ++b) {
    if (progress) progress(static_cast<double>(b) / static_cast<double>(beams.size()));
    MeasuredData data = measured_data_from_table(table, source, beams[b]);
    const bool referenced =
        std::all_of(data.has_true_range.begin(), data.has_true_range.end(), [](bool k) { return k; });
    if (!referenced) {
      out.beams_without_reference.push_back(beams[b]);
      continue;
    }
    const core::StillSegmentation s =
        still_surfaces(data.range_time_s, data.range_mm, calibration.model.mixture, still);
    std::vector<bool> counted(s.episode.size());
    for (std::size_t k = 0; k < counted.size(); ++k) counted[k] = s.episode[k] != core::kSetApart;
    BeamScore score;
    score.set_apart = static_cast<long>(std::count(counted.begin(), counted.end(), false));
    score.compensation = compensate(data, calibration, junctions.at(data));
    score.windows =
        evaluate_windows(data, calibration, score.compensation, windows, stride, {}, counted, band);
    score.data = std::move(data);
    out.beams.push_back(std::move(score));
  }
  if (out.beams.empty()) {
    throw core::InvalidInput(source + ": no beam has a reference distance (true_range_mm) on " +
                             "every range: nothing to score the calibration against");
  }
  std::vector<std::vector<WindowEvaluation>> per_beam;
  per_beam.reserve(out.beams.size());
  for (const BeamScore& s : out.beams) per_beam.push_back(s.windows);
  out.pooled = pool_window_evaluations(per_beam);
  if (progress) progress(1.0);
  return out;
}

}  // namespace tofcomp::calibration
