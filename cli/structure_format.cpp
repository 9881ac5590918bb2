#include "cli/structure_format.hpp"

#include <fmt/format.h>

#include <map>

#include "cli/mixture_format.hpp"
namespace tofcomp::cli {
namespace {

constexpr const auto& kLevels = core::kKalmanNoiseLevels;
constexpr std::array<const char*, core::kKalmanNoiseLevelCount> kLevelKeys = {
    "case_process_psd_k2_per_s", "junction_process_psd_k2_per_s", "measurement_variance_k2"};

const char* mark(int index, const core::StructureChoice& choice) {
  if (index == choice.chosen) return "chosen";
  if (index == choice.best_by_held_out) return "best held-out";
  return "";
}

// The best held-out log-likelihood per range at each number of modes the search tried.
std::map<int, double> best_held_out_by_modes(const core::StructureChoice& choice) {
  std::map<int, double> out;
  for (const core::CandidateEvidence& e : choice.candidates) {
    if (!e.ok) continue;
    const auto [at, inserted] = out.emplace(e.modes, e.held_out_log_likelihood);
    if (!inserted) at->second = std::max(at->second, e.held_out_log_likelihood);
  }
  return out;
}

}  // namespace

nlohmann::json to_json(const core::KalmanNoiseFit& fit) {
  nlohmann::json levels = nlohmann::json::object();
  for (std::size_t i = 0; i < kLevels.size(); ++i) {
    const core::KalmanNoiseLevelFit& l = fit.levels[i];
    levels[kLevelKeys[i]] = {{"value", l.value},
                             {"held", l.held},
                             {"start_drop", l.start_drop},
                             {"profile_drop_down", l.profile_drop_down},
                             {"profile_drop_up", l.profile_drop_up}};
  }
  return {{"method", "innovations' likelihood"},
          {"levels", levels},
          {"log_likelihood", fit.log_likelihood},
          {"start_log_likelihood", fit.start_log_likelihood},
          {"filter_passes", fit.evaluations}};
}

nlohmann::json to_json(const core::StructureChoice& choice) {
  nlohmann::json candidates = nlohmann::json::array();
  for (const core::CandidateEvidence& e : choice.candidates) {
    nlohmann::json c = {{"name", e.name},     {"family", e.family},
                        {"order", e.order},   {"modes", e.modes},
                        {"parameters", e.parameters}, {"ok", e.ok}};
    if (e.ok) {
      c["held_out_log_likelihood_per_range"] = e.held_out_log_likelihood;
      c["log_likelihood"] = e.log_likelihood;
      c["glr"] = e.glr;
      c["bic"] = e.bic;
    } else {
      c["error"] = e.error;
    }
    candidates.push_back(c);
  }
  auto name_of = [&](int index) -> nlohmann::json {
    if (index < 0) return nullptr;
    return choice.candidates[static_cast<std::size_t>(index)].name;
  };
  return {{"method", "one standard error rule on the held-out log-likelihood, interleaved folds"},
          {"chosen", name_of(choice.chosen)},
          {"basis", choice.basis.describe()},
          {"modes", choice.modes},
          {"best_by_held_out", name_of(choice.best_by_held_out)},
          {"best_by_glr", name_of(choice.best_by_glr)},
          {"best_by_bic", name_of(choice.best_by_bic)},
          {"shortfall_per_range", choice.shortfall_per_range},
          {"shortfall_standard_error", choice.shortfall_standard_error},
          {"held_out_ranges", choice.held_out_ranges},
          {"null_log_likelihood", choice.null_log_likelihood},
          {"candidates", candidates}};
}

nlohmann::json to_json(const calibration::JunctionDynamicsFit& fit) {
  const auto point = [](const calibration::JunctionDynamicsPoint& p) {
    return nlohmann::json{{"rise_k", p.dynamics.rise_k},
                          {"time_constant_s", p.dynamics.time_constant_s},
                          {"ranges_log_likelihood", p.ranges_log_likelihood},
                          {"prior_cost", p.prior_cost}};
  };
  return {{"datasheet",
           {{"rise_k", fit.datasheet.rise_k}, {"time_constant_s", fit.datasheet.time_constant_s}}},
          {"case_log_fit", point(fit.start)},
          {"best", point(fit.best)},
          {"block_t", fit.block_t},
          {"block_p", fit.block_p},
          {"replaced", fit.replaced},
          {"replaced_untested", fit.replaced_untested},
          {"junction_noise",
           fit.held_junction_noise_start
               ? nlohmann::json{{"case_log_q_j", fit.case_log_noise.junction_process_psd_k2_per_s},
                                {"held_q_j", fit.held_junction_noise->junction_process_psd_k2_per_s},
                                {"held_fit", point(*fit.held_junction_noise_start)},
                                {"block_t", fit.noise_block_t},
                                {"block_p", fit.noise_block_p},
                                {"held", fit.junction_noise_held}}
               : nlohmann::json(nullptr)},
          {"chosen_q_j", fit.chosen_noise().junction_process_psd_k2_per_s},
          {"refused_by_final_fit", fit.refused_by_final_fit.empty()
                                       ? nlohmann::json(nullptr)
                                       : nlohmann::json(fit.refused_by_final_fit)},
          {"evaluations", fit.evaluated.size()}};
}

nlohmann::json choices_json(const calibration::Training& training) {
  return {{"kalman_noise",
           training.kalman_noise_fit ? to_json(*training.kalman_noise_fit) : nlohmann::json(nullptr)},
          {"structure",
           training.structure ? to_json(*training.structure) : nlohmann::json(nullptr)},
          {"junction_dynamics", training.junction_dynamics
                                    ? to_json(*training.junction_dynamics)
                                    : nlohmann::json(nullptr)},
          {"gross_errors",
           {{"ranges", training.gross_errors.count},
            {"share", training.gross_errors.share()},
            {"beyond_mm", calibration::kGrossErrorMm}}}};
}

std::string kalman_noise_text(const core::KalmanNoiseFit& fit) {
  std::string out = fmt::format(
      "junction filter noise (§3.3), by the innovations' likelihood (log-likelihood {:.1f}, "
      "{:+.1f} over the LMS 200 levels):\n",
      fit.log_likelihood, fit.log_likelihood - fit.start_log_likelihood);
  for (std::size_t i = 0; i < kLevels.size(); ++i) {
    const core::KalmanNoiseLevelFit& l = fit.levels[i];
    out += fmt::format("  {:<28} {:10.3g}  {}  (log-likelihood lost ×0.1: {:.1f}, ×10: {:.1f})\n",
                       core::kalman_noise_level_name(kLevels[i]), l.value,
                       l.held ? "held: the log does not reject the LMS 200 level" : "fitted",
                       l.profile_drop_down, l.profile_drop_up);
  }
  return out;
}

std::string structure_text(const core::StructureChoice& choice) {
  std::string out =
      "structure of Eq. 8 (§7): the fewest parameters within one standard error of the best "
      "log-likelihood of held-out ranges (interleaved folds); Algorithm 2's GLR and BIC beside:\n";
  out += fmt::format("  {:<40} {:>5} {:>12} {:>12} {:>14}\n", "candidate", "par.", "held-out/rng",
                     "GLR", "BIC");
  for (std::size_t i = 0; i < choice.candidates.size(); ++i) {
    const core::CandidateEvidence& e = choice.candidates[i];
    if (!e.ok) {
      out += fmt::format("  {:<40} {:>5} failed: {}\n", e.name, e.parameters, e.error);
      continue;
    }
    out += fmt::format("  {:<40} {:>5} {:12.5f} {:12.1f} {:14.1f} {}\n", e.name, e.parameters,
                       e.held_out_log_likelihood, e.glr, e.bic,
                       mark(static_cast<int>(i), choice));
  }
  const core::CandidateEvidence& chosen = choice.candidates[static_cast<std::size_t>(choice.chosen)];
  out += fmt::format(
      "  chosen: {} ({:.5f} ± {:.5f} per held-out range below the best, on {} held-out ranges); "
      "GLR would take {}, BIC {}\n",
      chosen.name, choice.shortfall_per_range, choice.shortfall_standard_error,
      choice.held_out_ranges,
      choice.candidates[static_cast<std::size_t>(choice.best_by_glr)].name,
      choice.candidates[static_cast<std::size_t>(choice.best_by_bic)].name);
  return out;
}

// The ranges' verdict on the case log's q_j, when it had raised it; empty otherwise.
std::string junction_noise_text(const calibration::JunctionDynamicsFit& fit) {
  if (!fit.held_junction_noise_start) return "";
  return fmt::format(
      "  junction process noise q_j: the case log's {:.3g} K²/s {} by the ranges against {:.3g} "
      "(its start; log-likelihood {:+.1f} there, over blocks of {} t = {:.2f}, p = {:.2g}){}\n",
      fit.case_log_noise.junction_process_psd_k2_per_s,
      fit.junction_noise_held ? "rejected" : "not rejected",
      fit.held_junction_noise->junction_process_psd_k2_per_s,
      fit.held_junction_noise_start->ranges_log_likelihood - fit.start.ranges_log_likelihood,
      calibration::kJunctionBlockRanges, fit.noise_block_t, fit.noise_block_p,
      fit.chosen_holds_junction_noise() ? ": the calibration's filter holds it there" : "");
}

std::string junction_dynamics_text(const calibration::JunctionDynamicsFit& fit) {
  const calibration::JunctionDynamics& chosen = fit.chosen().dynamics;
  return fmt::format(
      "junction dynamics (§3.2-§3.3), by the ranges' likelihood and the datasheet prior: "
      "rise P·R1 {:.2f} K, time constant R1·C1 {:.1f} s ({}; case-log fit {:.2f} K, {:.1f} s; "
      "datasheet {:.2f} K, {:.1f} s; the ranges' log-likelihood {:+.1f}, over blocks of {} t = {:.2f}, "
      "p = {:.2g}; {} points)\n",
      chosen.rise_k, chosen.time_constant_s,
      fit.replaced_untested
          ? "from the ranges, untested: the junction re-check's alternative to the case-log fit's"
      : fit.replaced ? "from the ranges: they reject the case-log fit's junction"
      : fit.refused_by_final_fit.empty()
          ? "the case-log fit's: the ranges do not reject it"
          : "the case-log fit's: the ranges reject it, but the final fit failed on their junction: " +
                fit.refused_by_final_fit,
      fit.start.dynamics.rise_k, fit.start.dynamics.time_constant_s, fit.datasheet.rise_k,
      fit.datasheet.time_constant_s,
      fit.best.ranges_log_likelihood - fit.start.ranges_log_likelihood,
      calibration::kJunctionBlockRanges, fit.block_t, fit.block_p, fit.evaluated.size()) +
         junction_noise_text(fit);
}

std::string choices_text(const calibration::Training& training) {
  std::string out;
  out += training.kalman_noise_fit ? kalman_noise_text(*training.kalman_noise_fit)
                               : "junction filter noise (§3.3): as given (--kalman-noise)\n";
  if (training.structure) {
    out += structure_text(*training.structure);
  } else if (training.structure_not_chosen) {
    out += "structure of Eq. 8: too few ranges to judge candidates on; the paper's (§8) for what "
           "was not given\n";
  } else {
    out += "structure of Eq. 8: as given (--basis, --modes)\n";
  }
  for (const std::string& dropped : training.final_fit_dropped_modes) {
    out += "  the final fit dropped " + dropped + "\n";
  }
  if (training.structure && !training.final_fit_dropped_modes.empty()) {
    out += "  trained with " + std::to_string(training.em.mixture.modes()) + " modes\n";
  }
  if (training.junction_dynamics) out += junction_dynamics_text(*training.junction_dynamics);
  if (training.gross_errors.count > 0) {
    out += calibration::gross_errors_note(training.gross_errors) + "\n";
  }
  return out;
}

std::string trained_model_text(const core::Calibration& calibration,
                               const core::StructureChoice* choice) {
  const core::MixtureParameters& m = calibration.model.mixture;
  std::string out = fmt::format("the trained model (the search's start): basis {}, {} {}",
                                calibration.model.basis.describe(), m.modes(),
                                m.modes() == 1 ? "mode" : "modes");
  if (choice == nullptr) {
    out += " (as given)\n";
  } else {
    out += " (chosen from the data, §7); the best held-out log-likelihood per range with";
    for (const auto& [modes, best] : best_held_out_by_modes(*choice)) {
      out += fmt::format(" {} {}: {:.4f};", modes, modes == 1 ? "mode" : "modes", best);
    }
    out.back() = '\n';
  }
  return out + modes_text(m);
}

nlohmann::json trained_model_json(const core::Calibration& calibration,
                                  const core::StructureChoice* choice) {
  nlohmann::json by_modes = nullptr;
  if (choice != nullptr) {
    by_modes = nlohmann::json::object();
    for (const auto& [count, best] : best_held_out_by_modes(*choice)) {
      by_modes[std::to_string(count)] = best;
    }
  }
  return {{"basis", calibration.model.basis.describe()},
          {"modes", calibration.model.mixture.modes()},
          {"mixture", modes_json(calibration.model.mixture)},
          {"chosen_from_data", choice != nullptr},
          {"best_held_out_log_likelihood_by_modes", by_modes}};
}

}  // namespace tofcomp::cli
