// tofcomp diagnose DATA: closes the loop on data with a known distance. Trains the paper's model
// (or takes --calibration), searches the grammar of what Eq. 8 may lack on held-out ranges
// (calibration/model_search.hpp), keeps terms past a family-wise false-alarm level, and reports
// the held-out error of d̂ before and after against the Cramér–Rao bound; the residual tests
// (core/residual_diagnosis.hpp) follow as evidence.

#include "calibration/compensation.hpp"
#include "calibration/covariates.hpp"
#include "calibration/diagnosis.hpp"
#include "calibration/junction_estimate.hpp"
#include "calibration/model_search.hpp"
#include "calibration/trained_search.hpp"
#include "cli/command.hpp"
#include "cli/findings_format.hpp"
#include "cli/junction_recheck_format.hpp"
#include "cli/kept_terms_note.hpp"
#include "cli/number_checks.hpp"
#include "cli/progress.hpp"
#include "cli/report_options.hpp"
#include "cli/search_format.hpp"
#include "cli/shared_options.hpp"
#include "cli/structure_format.hpp"
#include "cli/structure_recheck_format.hpp"
#include "io/atomic_file.hpp"
#include "io/calibration_file.hpp"
#include "io/covariates_csv.hpp"

namespace tofcomp::cli {
namespace {

struct SearchSettings {
  std::string calibration;  // empty: train one
  std::string calibration_output;
  std::string covariates_output;
  int threads = 0;
};

// The paper's model the search started from, the smoothed junction temperature under it, and
// the search; with the junction re-checked when training chose it
// (calibration/junction_recheck.hpp).
struct Searched {
  core::Calibration calibration;
  calibration::SmoothedJunction junction;
  std::optional<core::StructureChoice> structure;  // when training chose it from the data
  calibration::ModelSearchResult search;
  std::optional<calibration::JunctionRecheck> junction_recheck;
  std::optional<calibration::StructureRecheck> structure_recheck;
};

Searched search_from(const calibration::MeasuredData& measured, const SearchSettings& s,
                     const calibration::TrainSettings& training,
                     const calibration::ModelSearchOptions& options, Progress& progress) {
  const auto searching = [&](double share, const std::string& stage) {
    progress.update(0.2 + 0.6 * share, stage);
  };
  if (!s.calibration.empty()) {
    core::Calibration c = io::read_calibration_file(s.calibration);
    calibration::SmoothedJunction junction =
        calibration::junction_at_ranges(measured, c.thermal, c.kalman_noise, c.ambient_c);
    calibration::ModelSearchResult search =
        calibration::search_model(measured, c, junction, options, searching);
    return {std::move(c),      std::move(junction), std::nullopt,
            std::move(search), std::nullopt,        std::nullopt};
  }
  progress.update(0.0, "training the paper's model");
  calibration::TrainSettings settings = training;
  settings.threads = s.threads;
  calibration::Training trained_model = calibration::train_calibration(
      measured, settings, nullptr, [&](double share, const std::string& stage) {
        progress.update(0.4 * share, "training: " + stage);
      });
  calibration::TrainedSearch trained = calibration::search_and_recheck(
      measured, settings, options, std::move(trained_model),
      [&](double share, const std::string& stage) { progress.update(0.4 + 0.55 * share, stage); });
  return {std::move(trained.training.calibration), std::move(trained.training.junction),
          std::move(trained.training.structure),   std::move(trained.search),
          std::move(trained.junction_recheck),     std::move(trained.structure_recheck)};
}

// The grammar's covariates at each range and the base model's centred residual y − d − Hθ̂ − Σ π μ.
void write_covariates(const calibration::MeasuredData& measured, const Searched& base,
                      const std::string& file) {
  const calibration::Compensation compensation =
      calibration::compensate(measured, base.calibration, base.junction);
  const Eigen::VectorXd residual =
      (measured.range_mm - measured.true_range_mm - compensation.bias_mm).array() -
      base.calibration.model.mixture.mean_offset();
  const core::CovariateTable covariates =
      calibration::covariate_table(measured, compensation.junction);
  io::write_file_atomically(file, [&](std::ostream& out) {
    io::write_covariates_csv(out, measured.range_time_s, residual, covariates);
  });
}

}  // namespace

void register_diagnose(CLI::App& app, const CommonOptions& common, CommandRunner& run) {
  auto* cmd = app.add_subcommand(
      "diagnose",
      "Search what the paper's model (Eq. 8) lacks: every parameter against every covariate, "
      "and more structure, judged on held-out ranges; keep what passes a family-wise "
      "false-alarm level and report d hat's held-out error before and after");
  auto data = add_data_options(*cmd);
  auto training = add_training_options(*cmd);
  auto s = std::make_shared<SearchSettings>();
  cmd->add_option("--calibration", s->calibration,
                  "A calibration trained on these data to start from (default: train one)")
      ->check(CLI::ExistingFile);
  auto search_options = add_search_options(*cmd);
  add_parallelism_option(*cmd, "--threads", s->threads,
                         "Fits (the structure search's folds, the model search's candidates) run");
  cmd->add_option("--calibration-output", s->calibration_output,
                  "Write the calibration with the kept terms (for tofcomp test, replay and "
                  "tofcompd); the trained one when the search kept nothing")
      ->type_name("FILE");
  cmd->add_option("--covariates-output", s->covariates_output,
                  "Write the covariates the search tried at each range, with the trained model's "
                  "centred residual, as CSV (to plot one against the other; columns in "
                  "docs/closing-the-loop.md)")
      ->type_name("FILE");
  auto report = add_report_options(*cmd);
  cmd->callback([&common, &run, data, training, s, search_options, report] {
    run = [&common, data, training, s, search_options, report] {
      report->check_if_requested();
      Progress progress("diagnose", !common.quiet);
      const calibration::MeasuredData measured = data->load();
      measured.require_true_ranges();
      const calibration::ModelSearchOptions options = search_options->options(s->threads);
      const Searched base = search_from(measured, *s, training->settings(), options, progress);
      const calibration::ModelSearchResult& search = base.search;
      if (!s->covariates_output.empty()) write_covariates(measured, base, s->covariates_output);
      progress.update(0.95, "the residual tests");
      const core::Diagnosis tests = calibration::diagnose(measured, base.calibration, s->threads);
      progress.done();

      const core::StructureChoice* structure = base.structure ? &*base.structure : nullptr;
      CommandResult result;
      result.json = {{"search", to_json(search, options)},
                     {"named", kept_names(search)},
                     {"findings", to_json(tests)},
                     {"trained_model", trained_model_json(base.calibration, structure)},
                     {"junction_recheck", base.junction_recheck ? to_json(*base.junction_recheck)
                                                                : nlohmann::json(nullptr)},
                     {"structure_recheck", base.structure_recheck ? to_json(*base.structure_recheck)
                                                                  : nlohmann::json(nullptr)}};
      result.text = search_text(search, options);
      if (base.junction_recheck) result.text += junction_recheck_text(*base.junction_recheck);
      if (base.structure_recheck) result.text += structure_recheck_text(*base.structure_recheck);
      result.text += trained_model_text(base.calibration, structure);
      result.text += "\nevidence: the residual tests of the trained model\n";
      result.text += diagnosis_text(tests);
      // Nothing kept: the trained calibration, written all the same (as calibrate-dir does).
      if (!s->calibration_output.empty()) {
        io::write_calibration_file(s->calibration_output,
                                   calibration::calibration_to_deploy(base.calibration, &search));
      }
      result.text += kept_terms_note(!search.kept.empty(), s->calibration_output);
      report->write_if_requested(measured, training->settings(), result.json, base.calibration,
                                 search, tests, options.windows, !common.quiet);
      return result;
    };
  });
}

}  // namespace tofcomp::cli
