#include "cli/beam_scores_format.hpp"

#include <fmt/format.h>

#include "cli/report_format.hpp"

namespace tofcomp::cli {
namespace {

long ranges_of(const calibration::BeamScores& scores) {
  long n = 0;
  for (const auto& b : scores.beams) n += static_cast<long>(b.data.range_mm.size());
  return n;
}

// "MAE / bound" of d̂ at each window length, or "-" where no window was scored.
std::string ratios_text(const std::vector<calibration::WindowEvaluation>& windows) {
  std::string out;
  for (const auto& e : windows) {
    if (!out.empty()) out += " ";
    out += e.has_truth && e.em.count > 0
               ? fmt::format("{:.2f}", e.em.mean_absolute_error / e.cramer_rao_mae_mm)
               : std::string("-");
  }
  return out;
}

}  // namespace

nlohmann::json beam_scores_json(const calibration::BeamScores& scores) {
  nlohmann::json beams = nlohmann::json::array();
  for (const auto& b : scores.beams) {
    beams.push_back({{"beam", b.data.beam},
                     {"ranges", b.data.range_mm.size()},
                     {"set_apart", b.set_apart},
                     {"windows", to_json(b.windows)}});
  }
  return {{"windows", to_json(scores.pooled)},
          {"samples", ranges_of(scores)},
          {"still_gate_mm", scores.still_gate_mm},
          {"beams", beams},
          {"beams_without_reference", scores.beams_without_reference}};
}

std::string beam_scores_text(const calibration::BeamScores& scores) {
  std::string out;
  if (scores.beams.size() > 1) {
    out += fmt::format("{} beams with a reference, pooled:\n", scores.beams.size());
  }
  out += window_table_text(scores.pooled);
  std::string lengths;
  for (const auto& e : scores.pooled) lengths += (lengths.empty() ? "" : "/") + std::to_string(e.window);
  out += fmt::format(
      "still surfaces (gate {:.1f} mm): windows holding a range that is not still left out\n",
      scores.still_gate_mm);
  out += fmt::format("{:>6} {:>9} {:>10} {:>18}  MAE EM / bound\n", "beam", "ranges",
                     "set apart", "windows left out", lengths);
  out += fmt::format("{:>6} {:>9} {:>10} {:>18}  at {}\n", "", "", "", "at " + lengths, lengths);
  for (const auto& b : scores.beams) {
    std::string left_out;
    for (const auto& e : b.windows) {
      left_out += (left_out.empty() ? "" : "/") + std::to_string(e.windows_left_out);
    }
    out += fmt::format("{:>6} {:>9} {:>10} {:>18}  {}\n", b.data.beam, b.data.range_mm.size(),
                       b.set_apart, left_out, ratios_text(b.windows));
  }
  if (!scores.beams_without_reference.empty()) {
    out += fmt::format("{} beams without a reference on every range not scored\n",
                       scores.beams_without_reference.size());
  }
  return out;
}

}  // namespace tofcomp::cli
