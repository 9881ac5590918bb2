#include "cli/search_figure_data.hpp"

#include <fmt/format.h>

#include <cmath>
#include <string>
#include <vector>

#include "cli/mixture_format.hpp"
#include "cli/search_residuals.hpp"
#include "cli/term_figure_tables.hpp"
#include "core/error.hpp"
#include "io/atomic_file.hpp"

namespace tofcomp::cli {
namespace {

nlohmann::json vector_json(const Eigen::VectorXd& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

nlohmann::json matrix_json(const Eigen::MatrixXd& m) {
  nlohmann::json out = nlohmann::json::array();
  for (Eigen::Index r = 0; r < m.rows(); ++r) out.push_back(vector_json(m.row(r).transpose()));
  return out;
}

// A term to draw: the term, the step that named it, and whether the final model holds it (kept
// by its step and not dropped after a later one).
struct FigureTerm {
  core::Term term;
  int step = 0;  // 1-based
  bool kept = false;
  const calibration::CandidateResult* named = nullptr;
  const calibration::SearchStep* search_step = nullptr;
};

// The kept terms (as fitted on all the data) with their steps, then the candidate the last step
// named and did not keep.
std::vector<FigureTerm> figure_terms(const calibration::ModelSearchResult& search) {
  std::vector<FigureTerm> out;
  // The terms training's calibration brought have no step: the steps' kept terms follow them.
  auto kept = static_cast<std::size_t>(search.carried_from_training);
  for (std::size_t s = 0; s < search.steps.size(); ++s) {
    const calibration::SearchStep& step = search.steps[s];
    const calibration::CandidateResult* named = step.named();
    if (!named) continue;
    const bool held = step.held() && kept < search.kept.size();
    out.push_back(
        {held ? search.kept[kept++] : named->term, static_cast<int>(s) + 1, held, named, &step});
  }
  return out;
}

const char* figure_kind(const core::Term& t) {
  switch (t.parameter) {
    case core::Parameter::Bias:
    case core::Parameter::ModeOffset:
      return "curve";
    case core::Parameter::Spread:
    case core::Parameter::Weights:
      return "bins";
    case core::Parameter::Markov:
      return "runs";
    case core::Parameter::ExtraMode:
    case core::Parameter::Outliers:
      break;
  }
  return "density";
}

[[noreturn]] void missing(const core::Term& t) {
  throw core::InvalidInput("the calibration's extension lacks the kept term " + t.describe());
}

const core::MeanTermFit* mean_fit(const core::Calibration& c, const core::Term& t) {
  if (!c.extension) missing(t);
  for (const core::MeanTermFit& f : c.extension->mean_terms) {
    if (f.term.parameter == t.parameter && f.term.covariate == t.covariate &&
        f.term.form == t.form && f.term.mode == t.mode) {
      return &f;
    }
  }
  missing(t);
}

const core::NoiseBins* bins_fit(const core::Calibration& c, const core::Term& t) {
  if (!c.extension) missing(t);
  const core::ExtendedMixture& m = c.extension->extended_mixture;
  const std::optional<core::NoiseBins>& bins =
      t.parameter == core::Parameter::Spread ? m.variance_bins : m.weight_bins;
  if (!bins || bins->term.covariate != t.covariate) missing(t);
  return &*bins;
}

nlohmann::json term_json(const FigureTerm& f, int index) {
  const core::Term& t = f.term;
  nlohmann::json out{{"index", index},
                     {"step", f.step},
                     {"kept", f.kept},
                     {"effect", core::effect_name(t.label())},
                     {"term", t.describe()},
                     {"parameter", core::parameter_token(t.parameter)},
                     {"covariate", core::covariate_token(t.covariate)},
                     {"covariate_unit", core::covariate_unit(t.covariate)},
                     {"form", core::form_token(t.form)},
                     {"figure", figure_kind(t)},
                     {"p_value", f.named->p_value},
                     {"critical_p", f.search_step->critical_p},
                     {"held_out_gain", f.named->held_out_gain},
                     {"fitted", nullptr}};
  if (t.parameter == core::Parameter::ModeOffset) out["mode"] = t.mode + 1;
  if (t.needs_time_constant()) out["time_constant_s"] = t.time_constant_s;
  return out;
}

// Writes the tables of one term's figure, and what the calibration holds of it when kept.
void write_term(const std::filesystem::path& dir, const SearchResiduals& r,
                const core::Calibration& final, const FigureTerm& f, nlohmann::json& entry) {
  const core::Term& t = f.term;
  const std::string stem = fmt::format("term{}_", entry.at("index").get<int>());
  nlohmann::json files = nlohmann::json::object();
  const auto write = [&](const char* kind, const std::string& csv) {
    const std::string name = stem + kind + ".csv";
    io::write_file_atomically(dir / name, csv);
    files[kind] = name;
  };
  switch (t.parameter) {
    case core::Parameter::Bias:
    case core::Parameter::ModeOffset: {
      const core::MeanTermFit* fit = f.kept ? mean_fit(final, t) : nullptr;
      write("ranges", mean_term_ranges_csv(r, fit ? fit->term : t, fit));
      if (fit) {
        write("curve", mean_term_curve_csv(r, *fit));
        nlohmann::json fitted{{"coefficients_mm", vector_json(fit->coefficients)}};
        if (fit->term.needs_time_constant()) fitted["time_constant_s"] = fit->term.time_constant_s;
        if (fit->term.form == core::Form::Linear) {
          fitted["centre"] = fit->term.centre;
          fitted["scale"] = fit->term.scale;
          // f(c) = (c − centre) / scale: the coefficient per unit of the covariate.
          fitted["slope_mm_per_unit"] = fit->coefficients[0] / fit->term.scale;
          if (fit->term.has_covariate_range()) {
            fitted["covariate_range"] = {fit->term.covariate_low, fit->term.covariate_high};
          }
        }
        if (fit->term.form == core::Form::Smooth) fitted["knots"] = vector_json(fit->term.knots);
        entry["fitted"] = fitted;
      }
      break;
    }
    case core::Parameter::Spread:
    case core::Parameter::Weights: {
      const core::NoiseBins* fit = f.kept ? bins_fit(final, t) : nullptr;
      write("bins", bins_term_csv(r, fit ? fit->term : t, fit));
      if (fit) {
        entry["fitted"] = {{"edges", vector_json(fit->term.knots)},
                           {t.parameter == core::Parameter::Spread ? "variances_mm2" : "weights",
                            matrix_json(fit->table)}};
      }
      break;
    }
    case core::Parameter::Markov: {
      const Eigen::MatrixXd& a = r.mixture.transition;
      if (f.kept && a.size() == 0) missing(t);
      write("runs", runs_csv(r, f.kept ? &a : nullptr));
      if (f.kept) entry["fitted"] = {{"transition", matrix_json(a)}};
      break;
    }
    case core::Parameter::ExtraMode:
    case core::Parameter::Outliers:
      write("density", density_csv(r));
      if (f.kept && t.parameter == core::Parameter::Outliers) {
        if (!(r.mixture.outlier_weight > 0.0)) missing(t);
        entry["fitted"] = {{"outlier_weight", r.mixture.outlier_weight},
                           {"outlier_span_mm", 1.0 / r.mixture.outlier_density}};
      } else if (f.kept) {
        entry["fitted"] = {{"modes", modes_json(r.mixture.modes)}};
      }
      break;
  }
  entry["files"] = files;
}

}  // namespace

nlohmann::json write_search_figure_data(const std::filesystem::path& directory,
                                        const calibration::MeasuredData& measured,
                                        const core::Calibration& final,
                                        const calibration::ModelSearchResult& search) {
  const SearchResiduals r = search_residuals(measured, final);
  io::write_file_atomically(directory / "search_residuals.csv", residuals_csv(measured, r));
  nlohmann::json out = nlohmann::json::array();
  int index = 0;
  for (const FigureTerm& f : figure_terms(search)) {
    nlohmann::json entry = term_json(f, ++index);
    write_term(directory, r, final, f, entry);
    out.push_back(std::move(entry));
  }
  return out;
}

}  // namespace tofcomp::cli
