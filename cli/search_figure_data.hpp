// The data behind the figures of the model search (calibration/model_search.hpp) in the
// diagnosis report (cli/diagnosis_report.hpp), written into a directory for the renderer:
// one figure for each term the search kept, drawn as the search fitted it (the values the final
// calibration holds, which --calibration-output writes), and one for the candidate the last step
// named but did not keep, drawn with the data and the model held but no fitted effect.
//   search_residuals.csv  the whole record under the final calibration (cli/search_residuals.hpp):
//                         time_s, residual_mm (y − d − the bias with every bias term), mode (its
//                         most probable, −1 an outlier), e_mm (less that mode's offset)
//   term<N>_ranges.csv, term<N>_curve.csv   a bias or mode-offset term
//   term<N>_bins.csv      a spread or weights term
//   term<N>_runs.csv      the Markov chain
//   term<N>_density.csv   one more mode, outliers
// (the columns: cli/term_figure_tables.hpp).
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>

#include "calibration/measured_data.hpp"
#include "calibration/model_search.hpp"
#include "core/calibration.hpp"

namespace tofcomp::cli {

// Writes the files and returns their description, one entry per figure in the search's order:
// [{index (N), step (1-based), kept, effect, term, parameter, covariate, covariate_unit, form,
//   mode (1-based, a mode-offset term), p_value, critical_p, held_out_gain,
//   figure ("curve", "bins", "runs" or "density"), files {ranges, curve, bins, runs, density},
//   fitted: what the calibration holds of a kept term, as its file has it (null when not kept):
//   {coefficients_mm, time_constant_s, centre, scale, slope_mm_per_unit and covariate_range
//   (linear; the range only where the term holds beyond it), knots} of a bias
//   or offset term,
//   {edges, variances_mm2 | weights} of bins, {transition}, {outlier_weight, outlier_span_mm},
//   {modes: [{offset_mm, std_mm, weight}]}}].
// `final` is search.calibration (or a calibration read back from its file). Throws
// core::InvalidInput when a kept term is missing from the calibration's extension.
nlohmann::json write_search_figure_data(const std::filesystem::path& directory,
                                        const calibration::MeasuredData& measured,
                                        const core::Calibration& final,
                                        const calibration::ModelSearchResult& search);

}  // namespace tofcomp::cli
