// tofcomp test DATA --calibration C.yaml: estimate d on windows with a trained calibration
// (§6, §8.4) on every beam with a reference distance (or the one --beam names), windows holding
// a range that is not still left out, and the three estimators' errors.
#include "cli/command.hpp"

#include "calibration/beam_scores.hpp"
#include "cli/beam_scores_format.hpp"
#include "cli/figure_drawing.hpp"
#include "cli/number_checks.hpp"
#include "cli/progress.hpp"
#include "cli/report_format.hpp"
#include "cli/shared_options.hpp"
#include "io/measured_data_csv.hpp"

namespace tofcomp::cli {

void register_test(CLI::App& app, const CommonOptions& common, CommandRunner& run) {
  auto* cmd = app.add_subcommand(
      "test",
      "Estimate the distance on windows of ranges with a calibration (EM testing) and "
      "report the errors of d̂, ȳ and mean(y − Hθ̂) − Σπμ on every beam with a reference "
      "(--beam: that one), windows holding a range that is not still left out");
  auto data = add_data_options(*cmd);
  auto calibration = std::make_shared<std::string>();
  auto windows = std::make_shared<std::string>("200,400,800");
  auto stride = std::make_shared<long>(1);
  auto figures = std::make_shared<std::string>();
  auto band_of = std::make_shared<std::string>();
  cmd->add_option("--calibration", *calibration, "Calibration file (from tofcomp train)")
      ->required()
      ->check(CLI::ExistingFile);
  add_windows_option(*cmd, *windows, "Window lengths");
  cmd->add_option("--stride", *stride, "Samples between window starts (1: every window)")
      ->capture_default_str()
      ->check(at_least(1));
  add_figures_option(*cmd, *figures);
  cmd->add_option("--band-of", *band_of,
                  "Calibration whose trained junction range inside and beyond are judged against "
                  "(a field calibration against its bench's band; default: the one tested)")
      ->check(CLI::ExistingFile);
  cmd->callback([&common, &run, data, calibration, windows, stride, figures, band_of] {
    run = [&common, data, calibration, windows, stride, figures, band_of] {
      Progress progress("test", !common.quiet);
      const std::optional<ReportRenderer> renderer =
          figures->empty() ? std::nullopt : std::optional(find_report_renderer());
      const core::Calibration c = io::read_calibration_file(*calibration);
      std::optional<core::Calibration> band;
      if (!band_of->empty()) {
        band = io::read_calibration_file(*band_of);
        if (!band->model.trained_junction_c) {
          throw core::InvalidInput(*band_of +
                                   " names no trained junction range "
                                   "(trained_junction_c): no band to judge against");
        }
      }
      const io::MeasurementTable table = io::read_measured_data_file(data->file);
      const calibration::BeamScores scores = calibration::score_beams(
          table, data->file, c, data->given_beam(), parse_windows(*windows), *stride,
          [&](double f) { progress.update(f, "beams"); }, band ? &band->model : nullptr);
      if (renderer) {
        if (scores.beams.size() != 1) {
          throw core::InvalidInput("--figures draws one beam; " + data->file + " has " +
                                   std::to_string(scores.beams.size()) +
                                   " with a reference: name one with --beam");
        }
        const calibration::BeamScore& b = scores.beams.front();
        progress.update(1.0, "drawing the figures");
        write_and_draw_figures(*figures,
                               FigureInputs{b.data, c, b.compensation, b.windows, *stride}, {},
                               *renderer, !common.quiet);
      }
      progress.done();
      CommandResult result;
      result.json = beam_scores_json(scores);
      result.text = beam_scores_text(scores);
      return result;
    };
  });
}

}  // namespace tofcomp::cli
