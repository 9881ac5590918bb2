#include "cli/field_training_format.hpp"

#include <fmt/format.h>

#include "cli/report_format.hpp"

namespace tofcomp::cli {

nlohmann::json field_training_json(const calibration::FieldTraining& t) {
  nlohmann::json beams = nlohmann::json::array();
  for (const auto& b : t.beams) {
    beams.push_back({{"source", b.source},
                     {"beam", b.beam},
                     {"ranges", b.ranges},
                     {"with_reference", b.with_reference},
                     {"still", b.still},
                     {"episodes", b.episodes},
                     {"set_apart", b.set_apart}});
  }
  return {{"mode", "field"},
          {"bench_calibration_given", t.bench_given},
          {"beams", beams},
          {"ranges_used", t.ranges_used},
          {"ranges_with_reference", t.ranges_with_reference},
          {"episodes", t.episodes},
          {"still_gate_mm", t.gate_mm},
          {"distance_determined", t.em.distance_determined},
          {"constant", t.constant},
          {"basis", t.basis.basis.describe()},
          {"basis_held_out", t.basis.held_out},
          {"em", {{"iterations", t.em.iterations}, {"converged", t.em.converged}}}};
}

std::string field_training_text(const calibration::FieldTraining& t) {
  std::string text = fmt::format("{:<40} {:>5} {:>9} {:>9} {:>8} {:>9} {:>9}\n", "record", "beam",
                                 "ranges", "reference", "still", "episodes", "set apart");
  for (const auto& b : t.beams) {
    text += fmt::format("{:<40} {:>5} {:>9} {:>9} {:>8} {:>9} {:>9}\n", b.source, b.beam,
                        b.ranges, b.with_reference, b.still, b.episodes, b.set_apart);
  }
  text += fmt::format(
      "still: within {:.1f} mm of the surface's level; {} episodes, {} ranges fitted ({} of "
      "known distance)\nthe constant of d and the bias: {}\n",
      t.gate_mm, t.episodes, t.ranges_used, t.ranges_with_reference, t.constant);
  text += "basis by held-out time blocks (log-likelihood per range):";
  const std::string chosen = t.basis.basis.describe();
  for (const auto& [name, score] : t.basis.held_out) {
    text += fmt::format("\n  {} {}: {:.4f}", name == chosen ? "*" : " ", name, score);
  }
  text += "\n";
  if (!t.em.distance_determined) {
    text += t.bench_given ? "absolute distances carry the bench calibration's offset: no range "
                            "of these records has a reference\n"
                          : "absolute distances carry the device's own offset: no range of these "
                            "records has a reference and no bench calibration was given\n";
  }
  text += calibration_text(t.calibration);
  text += "EM: " + std::to_string(t.em.iterations) + " iterations" +
          (t.em.converged ? "" : " (cap reached)") + "\n";
  return text;
}

}  // namespace tofcomp::cli
