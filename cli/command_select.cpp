// tofcomp select DATA [--datasheet D.yaml]: Algorithm 2 over candidate bases (§7): GLR against
// the single-Gaussian null, Eq. 25 and 29 as printed, BIC and held-out likelihood.
#include <fmt/format.h>

#include "calibration/basis_spec.hpp"
#include "cli/command.hpp"
#include "cli/progress.hpp"
#include "cli/shared_options.hpp"
#include "core/model_selection.hpp"

namespace tofcomp::cli {

void register_select(CLI::App& app, const CommonOptions& common, CommandRunner& run) {
  auto* cmd =
      app.add_subcommand("select",
                         "Choose H(.) among candidate bases (Algorithm 2): GLR, BIC and held-out "
                         "likelihood per candidate");
  auto data = add_data_options(*cmd);
  auto thermal = add_thermal_options(*cmd);
  auto candidates =
      std::make_shared<std::vector<std::string>>(std::vector<std::string>{"polynomial:1..8"});
  auto modes = std::make_shared<int>(2);
  cmd->add_option("--candidates", *candidates,
                  "Candidate bases; kind:LO..HI expands to one per order")
      ->capture_default_str()
      ->type_name("BASES");
  cmd->add_option("--modes", *modes, "Lasing modes M")->capture_default_str()->type_name("M");
  cmd->callback([&common, &run, data, thermal, candidates, modes] {
    run = [&common, data, thermal, candidates, modes] {
      Progress progress("select", !common.quiet);
      const calibration::MeasuredData measured = data->load();
      measured.require_true_ranges();
      const calibration::ThermalFitSettings settings = thermal->settings();
      const calibration::ThermalFit fit = calibration::fit_thermal(measured, nullptr, settings);
      core::ThermalNoise noise;
      const calibration::SmoothedJunction junction = calibration::junction_at_ranges(
          measured, fit.identified(), noise, settings.ambient_fallback_c);
      const auto bases = calibration::parse_candidates(*candidates, junction.junction_c);
      progress.update(0.2, std::to_string(bases.size()) + " candidates");
      core::SelectionOptions options;
      options.em.modes = *modes;
      const core::SelectionResult r = core::select_model(
          bases, junction.junction_c, measured.range_mm - measured.true_range_mm, options);
      progress.done();

      CommandResult result;
      result.json["null_log_likelihood"] = r.null_log_likelihood;
      result.json["candidates"] = nlohmann::json::array();
      std::string text =
          fmt::format("{:<28} {:>4} {:>12} {:>12} {:>12} {:>12} {:>10}\n", "candidate", "p", "GLR",
                      "Eq.25", "BIC", "held-out/n", "Eq.29");
      for (const auto& s : r.scores) {
        nlohmann::json j = {{"name", s.name}, {"columns", s.columns}, {"ok", s.ok}};
        if (s.ok) {
          j.update({{"log_likelihood", s.log_likelihood},
                    {"glr", s.glr},
                    {"paper_eq25", s.paper_eq25},
                    {"paper_eq29", s.paper_eq29},
                    {"bic", s.bic},
                    {"held_out_log_likelihood_per_sample", s.held_out_log_likelihood},
                    {"converged", s.converged}});
          text += fmt::format("{:<28} {:>4} {:>12.1f} {:>12.1f} {:>12.1f} {:>12.5f} {:>10.5f}\n",
                              s.name, s.columns, s.glr, s.paper_eq25, s.bic,
                              s.held_out_log_likelihood, s.paper_eq29);
        } else {
          j["error"] = s.error;
          text += fmt::format("{:<28} {:>4} failed: {}\n", s.name, s.columns, s.error);
        }
        result.json["candidates"].push_back(j);
      }
      auto name = [&](int i) {
        return i < 0 ? std::string("none") : r.scores[static_cast<std::size_t>(i)].name;
      };
      result.json["best_by_glr"] = name(r.best_by_glr);
      result.json["best_by_bic"] = name(r.best_by_bic);
      result.json["best_by_held_out"] = name(r.best_by_held_out);
      text += fmt::format(
          "best by GLR (Algorithm 2; grows with the order): {}\nbest by BIC: {}\nbest by "
          "held-out likelihood: {}\n",
          name(r.best_by_glr), name(r.best_by_bic), name(r.best_by_held_out));
      result.text = text;
      return result;
    };
  });
}

}  // namespace tofcomp::cli
