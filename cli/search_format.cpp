#include "cli/search_format.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <string>
#include <string_view>

namespace tofcomp::cli {
namespace {

// Candidates printed per step in the text (all of them are in the JSON).
constexpr std::size_t kCandidatesShown = 8;

nlohmann::json label_json(const core::Term& t) {
  const core::EffectLabel label = t.label();
  nlohmann::json out{{"effect", core::effect_name(label)},
                     {"parameter", core::label_parameter_token(label)},
                     {"covariate", core::label_covariate_token(label)},
                     {"form", core::form_token(t.form)},
                     {"term", t.describe()}};
  if (t.parameter == core::Parameter::ModeOffset) out["mode"] = t.mode + 1;
  if (t.needs_time_constant()) out["time_constant_s"] = t.time_constant_s;
  return out;
}

nlohmann::json candidate_json(const calibration::CandidateResult& c) {
  nlohmann::json out = label_json(c.term);
  if (!c.ok()) {
    out["error"] = c.error;
    return out;
  }
  out["held_out_gain"] = c.held_out_gain;
  out["gain_per_range"] = c.gain_per_range;
  out["t"] = c.t_statistic;
  out["p_value"] = c.p_value;
  out["screened_only"] = c.screened_only;
  if (c.compared_with_named) {
    out["t_below_named"] = c.t_below_named;
    out["p_below_named"] = c.p_below_named;
  }
  return out;
}

nlohmann::json errors_json(const std::vector<calibration::HeldOutError>& errors) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& e : errors) {
    out.push_back({{"window", e.window},
                   {"windows", e.windows},
                   {"before_mae_mm", e.before_mae_mm},
                   {"after_mae_mm", e.after_mae_mm},
                   {"mae_factor", e.before_mae_mm / e.after_mae_mm},
                   {"cramer_rao_mae_mm", e.cramer_rao_mae_mm}});
  }
  return out;
}

std::string errors_text(const std::vector<calibration::HeldOutError>& errors) {
  std::string text;
  for (const auto& e : errors) {
    text += fmt::format(
        "    window {:>4} ({:>5} windows): MAE of d hat {:.3f} -> {:.3f} mm (factor {:.2f}); "
        "Cramér–Rao bound {:.3f} mm: {:.2f} -> {:.2f} x\n",
        e.window, e.windows, e.before_mae_mm, e.after_mae_mm, e.before_mae_mm / e.after_mae_mm,
        e.cramer_rao_mae_mm, e.before_mae_mm / e.cramer_rao_mae_mm,
        e.after_mae_mm / e.cramer_rao_mae_mm);
  }
  return text;
}

std::string windows_not_compared_text(const calibration::ModelSearchResult& search) {
  std::string text;
  for (const Eigen::Index w : search.windows_not_compared) {
    text += fmt::format(
        "    window {:>4}: not compared: longer than this record's held-out blocks ({} ranges)\n",
        w, search.block);
  }
  return text;
}

}  // namespace

std::string effect_names(const std::vector<core::Term>& terms) {
  std::string out;
  for (const core::Term& t : terms) out += (out.empty() ? "" : ", ") + core::effect_name(t.label());
  return out;
}

std::string effect_names_or_nothing(const std::vector<core::Term>& terms) {
  const std::string out = effect_names(terms);
  return out.empty() ? "nothing" : out;
}

nlohmann::json term_descriptions(const std::vector<core::Term>& terms) {
  nlohmann::json out = nlohmann::json::array();
  for (const core::Term& t : terms) out.push_back(t.describe());
  return out;
}

std::string kept_names(const calibration::ModelSearchResult& search) {
  const std::string names = effect_names(search.kept);
  return names.empty() ? "none" : names;
}

nlohmann::json to_json(const calibration::ModelSearchResult& search,
                       const calibration::ModelSearchOptions& options) {
  nlohmann::json steps = nlohmann::json::array();
  for (const auto& s : search.steps) {
    nlohmann::json candidates = nlohmann::json::array();
    for (const auto& c : s.candidates) candidates.push_back(candidate_json(c));
    nlohmann::json alike = nlohmann::json::array();
    for (const calibration::CandidateResult* c : s.not_told_apart()) {
      alike.push_back(label_json(c->term));
    }
    nlohmann::json judged_again = nullptr;
    if (s.judged_again_after_step > 0) {
      judged_again = {{"after_step", s.judged_again_after_step},
                      {"held_out_gain", s.gain_beside_later},
                      {"t", s.t_beside_later},
                      {"p", s.p_beside_later},
                      {"dropped", s.dropped}};
    }
    steps.push_back({{"kept", s.kept},
                     {"judged_again", judged_again},
                     {"not_told_apart", alike},
                     {"critical_t", s.critical_t},
                     {"critical_p", s.critical_p},
                     {"family_wise_p", s.family_wise_p},
                     {"candidates", candidates},
                     {"errors", errors_json(s.errors)}});
  }
  nlohmann::json kept = nlohmann::json::array();
  for (const core::Term& t : search.kept) kept.push_back(label_json(t));
  nlohmann::json base = nlohmann::json::object(), final = nlohmann::json::object(),
                 bound = nlohmann::json::object(), factor = nlohmann::json::object(),
                 base_over_bound = nlohmann::json::object(),
                 final_over_bound = nlohmann::json::object();
  for (const auto& e : search.errors) {
    const std::string w = std::to_string(e.window);
    base[w] = e.before_mae_mm;
    final[w] = e.after_mae_mm;
    bound[w] = e.cramer_rao_mae_mm;
    factor[w] = e.before_mae_mm / e.after_mae_mm;
    base_over_bound[w] = e.before_mae_mm / e.cramer_rao_mae_mm;
    final_over_bound[w] = e.after_mae_mm / e.cramer_rao_mae_mm;
  }
  const calibration::CandidateResult* best =
      search.steps.empty() ? nullptr : search.steps.front().named();
  return {{"alpha", options.alpha},
          {"block", search.block},
          {"blocks", search.blocks},
          {"basis_directions_held", search.basis_directions_held},
          {"candidates_per_step", search.candidates_per_step},
          {"steps", steps},
          {"best", best ? label_json(best->term) : nlohmann::json(nullptr)},
          {"kept", kept},
          {"kept_from_training", search.carried_from_training},
          {"mae_mm", {{"base", base}, {"final", final}}},
          {"windows_not_compared", search.windows_not_compared},
          {"held_out_log_likelihood",
           {{"base", search.base_held_out_log_likelihood},
            {"final", search.final_held_out_log_likelihood()},
            {"scored_ranges", search.scored_ranges()}}},
          {"mae_factor", factor},
          {"cramer_rao_mae_mm", bound},
          {"mae_over_cramer_rao", {{"base", base_over_bound}, {"final", final_over_bound}}}};
}

std::string search_text(const calibration::ModelSearchResult& search,
                        const calibration::ModelSearchOptions& options) {
  std::string text = fmt::format(
      "model search: {} candidates of the grammar per step, each fitted on one of two folds "
      "({} blocks of {} ranges) and scored on the other, {}; kept at {:g} family-wise "
      "(max-T: the largest t of the step's candidates under sign flips of the same runs)\n",
      search.candidates_per_step, search.blocks, search.block,
      options.refined_effects > 0
          ? fmt::format("screened by short fits, each form of the best {} effects fitted to "
                        "convergence",
                        options.refined_effects)
          : std::string("each fitted to convergence"),
      options.alpha);
  if (search.basis_directions_held > 0) {
    text += fmt::format(
        "  {} of the bias's basis directions held at the training's fit: one fold holds too "
        "few ranges' worth of each to determine it\n",
        search.basis_directions_held);
  }
  text += search.kept.empty() ? "verdict: nothing kept: the paper's model explains the data\n"
                              : fmt::format("verdict: the model lacks {}\n", kept_names(search));
  for (int i = 0; i < search.carried_from_training; ++i) {
    text += fmt::format(
        "  from training: {}: the gross errors' outlier component, in every model compared\n",
        core::effect_name(search.kept[static_cast<std::size_t>(i)].label()));
  }
  for (std::size_t i = 0; i < search.steps.size(); ++i) {
    const auto& s = search.steps[i];
    const calibration::CandidateResult* named = s.named();
    if (!named) {
      text += fmt::format("  step {}: no candidate could be fitted\n", i + 1);
      continue;
    }
    text += fmt::format(
        "  step {}: named {} ({}): held-out gain {:.1f} nats ({:.2e} per range), t {:.2f} "
        "(p {:.2g}) {} {:.2f}, family-wise p {:.2g}: {}\n",
        i + 1, core::effect_name(named->term.label()), named->term.describe(),
        named->held_out_gain, named->gain_per_range, named->t_statistic, named->p_value,
        s.kept ? ">" : "<=", s.critical_t, s.family_wise_p, s.kept ? "kept" : "not kept");
    if (s.judged_again_after_step > 0) {
      text += fmt::format(
          "    judged again after step {}: beside the later terms, keeping it gains {:.1f} "
          "nats, t {:.2f} (p {:.2g}) {} {:g}: {}\n",
          s.judged_again_after_step, s.gain_beside_later, s.t_beside_later, s.p_beside_later,
          s.dropped ? "above" : "within", options.alpha, s.dropped ? "dropped" : "held");
    }
    const std::vector<const calibration::CandidateResult*> alike = s.not_told_apart();
    if (!alike.empty()) {
      text += fmt::format(
          "    not told apart from it on these data (its gain over each, run by run, p > {:g}):\n",
          calibration::kToldApartLevel);
      for (const calibration::CandidateResult* c : alike) {
        text +=
            fmt::format("      {} ({}): t {:.2f}, p {:.2g}\n", core::effect_name(c->term.label()),
                        c->term.describe(), c->t_below_named, c->p_below_named);
      }
    }
    text += errors_text(s.errors);
  }
  if (!search.errors.empty()) {
    text += "the held-out error of d hat, the trained model -> the final one:\n";
    text += errors_text(search.errors);
  }
  text += windows_not_compared_text(search);
  for (std::size_t i = 0; i < search.steps.size(); ++i) {
    const auto& s = search.steps[i];
    const std::size_t shown = std::min(kCandidatesShown, s.candidates.size());
    text += fmt::format(
        "step {} candidates (the first {} of {}; the named one, then by held-out gain):\n", i + 1,
        shown, s.candidates.size());
    // The effect and term columns as wide as their longest entry shown (an effect's name runs
    // to 50 characters), so that a long one never runs into the next column.
    std::size_t effect_width = std::string_view("effect").size();
    std::size_t term_width = std::string_view("term").size();
    for (std::size_t c = 0; c < shown; ++c) {
      effect_width = std::max(effect_width, core::effect_name(s.candidates[c].term.label()).size());
      term_width = std::max(term_width, s.candidates[c].term.describe().size());
    }
    text += fmt::format("  {:<{}}  {:<{}} {:>11} {:>8} {:>9}  {}\n", "effect", effect_width, "term",
                        term_width, "gain/range", "t", "p", "fit");
    for (std::size_t c = 0; c < shown; ++c) {
      const auto& r = s.candidates[c];
      if (!r.ok()) {
        text += fmt::format("  {:<{}}  {:<{}} not fitted: {}\n", core::effect_name(r.term.label()),
                            effect_width, r.term.describe(), term_width, r.error);
        continue;
      }
      text += fmt::format("  {:<{}}  {:<{}} {:>11.2e} {:>8.2f} {:>9.2g}  {}\n",
                          core::effect_name(r.term.label()), effect_width, r.term.describe(),
                          term_width, r.gain_per_range, r.t_statistic, r.p_value,
                          r.screened_only ? "screen" : "converged");
    }
  }
  return text;
}

}  // namespace tofcomp::cli
