#include "calibration/training.hpp"

#include <algorithm>

#include "calibration/basis_spec.hpp"
#include "calibration/final_fit.hpp"
#include "calibration/gross_errors.hpp"
#include "calibration/parallel_for.hpp"
#include "core/error.hpp"
#include "core/validation.hpp"
#include "io/utc_time.hpp"
#include "io/version.hpp"

namespace tofcomp::calibration {
namespace {

// Shares of the work, for progress: the search dominates when it runs.
constexpr double kThermalShare = 0.1;
constexpr double kNoiseShare = 0.2;
constexpr double kSearchShare = 0.8;
constexpr double kJunctionShare = 0.9;

// The paper's structure (§8), kept when a record is too short to choose one.
constexpr const char* kPaperBasis = "polynomial:4";
constexpr int kPaperModes = 2;

constexpr const char* kKalmanNoiseMethod = "innovations' likelihood (core/kalman_noise_fit.hpp)";
constexpr const char* kJunctionDynamicsMethod =
    "the ranges' likelihood with the datasheet prior, replacing the case-log fit's junction where "
    "a t-test over blocks of ranges rejects it (calibration/junction_dynamics.hpp)";
constexpr const char* kStructureMethod =
    "held-out log-likelihood on interleaved folds, one-standard-error rule "
    "(core/structure_search.hpp)";
constexpr const char* kStructureAgainMethod =
    "; chosen again on the ranges less the bias of the terms the model search kept "
    "(calibration/structure_recheck.hpp)";

void report(const TrainingProgress& progress, double share, const std::string& stage) {
  if (progress) progress(share, stage);
}

// The structure of Eq. 8: the user's basis and modes, or the search's choice among candidates.
core::StructureChoice choose_structure(const TrainSettings& settings,
                                       const Eigen::VectorXd& junction_c,
                                       const Eigen::VectorXd& y_minus_d,
                                       const TrainingProgress& progress) {
  core::StructureSearchOptions options = settings.search;
  if (settings.basis) options.basis = parse_basis(*settings.basis, junction_c);
  options.modes = settings.modes;
  if (!options.parallel_for) options.parallel_for = parallel_runner(settings.threads);
  int visited = 0;
  return core::search_structure(junction_c, y_minus_d, options,
                                [&](const core::CandidateEvidence& e) {
                                  ++visited;
                                  report(progress, kNoiseShare + (kSearchShare - kNoiseShare) *
                                                                     (1.0 - 1.0 / (1.0 + visited / 8.0)),
                                         "structure: " + e.name);
                                });
}

// The settings the structure search runs with: the fits on `runner`, the variance floor of
// ranges rounded to whole millimetres (below), held-out ranges scored by their rounded values.
TrainSettings structure_search_settings(const TrainSettings& settings,
                                        const core::ParallelFor& runner) {
  TrainSettings out = settings;
  if (!out.search.em.parallel_for) out.search.em.parallel_for = runner;
  out.search.em.variance_floor = std::max(out.search.em.variance_floor, rounding_variance_mm2());
  out.search.resolution = kRangeResolutionMm;
  return out;
}

// The choices' evidence as the calibration keeps it.
core::TrainingChoices record_choices(const Training& t, bool structure_given_again) {
  core::TrainingChoices choices;
  if (t.kalman_noise_fit) {
    core::KalmanNoiseRecord noise;
    noise.method = kKalmanNoiseMethod;
    for (const core::KalmanNoiseLevel level : core::kKalmanNoiseLevels) {
      if (t.kalman_noise_fit->levels[static_cast<std::size_t>(level)].held) {
        noise.held.emplace_back(core::kalman_noise_level_key(level));
      }
    }
    choices.kalman_noise = noise;
  }
  if (t.structure_not_chosen) {
    core::StructureRecord record;
    record.method =
        "not chosen: too few ranges to judge candidates on; the paper's structure (§8)";
    choices.structure = record;
  }
  if (t.structure) {
    const core::StructureChoice& s = *t.structure;
    auto name = [&](int index) { return s.candidates[static_cast<std::size_t>(index)].name; };
    core::StructureRecord record;
    record.method = kStructureMethod;
    if (structure_given_again) record.method += kStructureAgainMethod;
    record.chosen = name(s.chosen);
    record.best_by_glr = name(s.best_by_glr);
    record.best_by_bic = name(s.best_by_bic);
    for (const core::CandidateEvidence& e : s.candidates) {
      if (e.ok) {
        record.candidates.push_back(
            {e.name, e.parameters, e.held_out_log_likelihood, e.glr, e.bic});
      }
    }
    choices.structure = record;
  }
  if (t.junction_dynamics) {
    const JunctionDynamicsFit& j = *t.junction_dynamics;
    core::JunctionDynamicsRecord record;
    record.method = kJunctionDynamicsMethod;
    record.from_ranges = j.replaced;
    record.rise_k = j.chosen().dynamics.rise_k;
    record.time_constant_s = j.chosen().dynamics.time_constant_s;
    record.case_log_rise_k = j.start.dynamics.rise_k;
    record.case_log_time_constant_s = j.start.dynamics.time_constant_s;
    record.block_p = j.block_p;
    record.junction_noise_held = j.chosen_holds_junction_noise();
    choices.junction_dynamics = record;
  }
  return choices;
}

// The junction's dynamics from the ranges (calibration/junction_dynamics.hpp), at the structure
// chosen; the EM starts from the structure search's fit, or from a fit at the given structure.
JunctionDynamicsFit complete_junction(const MeasuredData& data, const TrainSettings& settings,
                                      const core::MapFitResult& case_fit,
                                      const core::ThermalNoise& noise,
                                      const std::optional<core::ThermalNoise>& held_junction_noise,
                                      const Eigen::VectorXd& junction_c, const core::Basis& basis,
                                      const core::EmTrainOptions& em,
                                      const std::optional<core::EmStartingPoint>& structure_fit) {
  JunctionDynamicsOptions options = settings.junction_dynamics;
  options.em = settings.search.em;
  // The points are compared by their likelihood alone (and its sums over blocks): the weight
  // rule, which waits out the slow exchange of weight between overlapping modes long after the
  // likelihood has settled, is off (on the day record of docs/performance.md, 1,587 → 1,292 EM
  // iterations over the 33 fits, the best point's log-likelihood gain +730.2 → +730.3 nats).
  options.em.weight_tolerance = core::kWeightRuleOff;
  options.em.variance_floor = em.variance_floor;
  options.em.parallel_for = em.parallel_for;
  core::EmStartingPoint start;
  if (structure_fit) {
    start = *structure_fit;
  } else {
    core::EmTrainOptions first = options.em;
    first.modes = em.modes;
    first.record_trace = false;
    const core::EmTrainResult fit = core::train_em(
        basis.design_matrix(junction_c), data.range_mm - data.true_range_mm, first);
    start = core::EmStartingPoint{fit.theta, fit.mixture};
  }
  const JunctionDynamicsProblem problem{data,
                                        case_fit,
                                        settings.thermal.prior,
                                        noise,
                                        held_junction_noise,
                                        settings.thermal.ambient_fallback_c,
                                        basis,
                                        em.modes,
                                        start};
  return fit_junction_dynamics(problem, options);
}

}  // namespace

Training train_calibration(const MeasuredData& data, const TrainSettings& settings,
                           const MeasuredData* held_out, const TrainingProgress& progress) {
  data.require_true_ranges();
  data.require_millimetre_ranges();
  Training t;
  report(progress, 0.0, "thermal fit");
  t.thermal = fit_thermal(data, held_out, settings.thermal);
  t.thermal_parameters = t.thermal.identified();

  report(progress, kThermalShare, "Kalman noise levels");
  core::ThermalNoise noise;
  if (settings.kalman_noise) {
    noise = *settings.kalman_noise;
  } else {
    t.kalman_noise_fit = core::fit_kalman_noise(case_log(data, settings.thermal.ambient_fallback_c),
                                                t.thermal_parameters, core::ThermalNoise{});
    noise = t.kalman_noise_fit->noise;
  }
  t.junction =
      junction_at_ranges(data, t.thermal_parameters, noise, settings.thermal.ambient_fallback_c);
  // Eq. 8 is fitted on the ranges a lasing mode can give; the gross errors join the calibration
  // as its outlier component (calibration/gross_errors.hpp). t.junction stays on every range.
  t.gross_errors = find_gross_errors(data);
  const bool has_gross_errors = t.gross_errors.count > 0;
  std::optional<MeasuredData> lasing_ranges;
  if (has_gross_errors) lasing_ranges = data.with_ranges(t.gross_errors.kept);
  const MeasuredData& fit_data = has_gross_errors ? *lasing_ranges : data;
  const auto at_fitted_ranges = [&](const Eigen::VectorXd& v) -> Eigen::VectorXd {
    return has_gross_errors ? Eigen::VectorXd(v(t.gross_errors.kept)) : v;
  };
  Eigen::VectorXd junction_c = at_fitted_ranges(t.junction.junction_c);
  const Eigen::VectorXd y_minus_d = fit_data.range_mm - fit_data.true_range_mm;

  core::EmTrainOptions em = settings.em;
  em.variance_floor = std::max(em.variance_floor, rounding_variance_mm2());
  // Every fit's sweeps on the threads asked for (the fits' answers do not depend on them).
  const core::ParallelFor runner = parallel_runner(settings.threads);
  if (!em.parallel_for) em.parallel_for = runner;
  core::Basis basis;
  std::optional<core::EmStartingPoint> structure_fit;
  const bool too_few_to_choose = y_minus_d.size() < core::minimum_ranges_for_search(settings.search);
  if (settings.structure_chosen) {
    t.structure = settings.structure_chosen;
    basis = basis_spanning(t.structure->basis, junction_c);
    em.modes = t.structure->modes;
    structure_fit = core::EmStartingPoint{t.structure->fit.theta, t.structure->fit.mixture};
  } else if ((settings.basis && settings.modes) || too_few_to_choose) {
    // Given, or too few ranges to judge candidates on: the paper's structure (§8) for what was
    // not given.
    basis = parse_basis(settings.basis.value_or(kPaperBasis), junction_c);
    em.modes = settings.modes.value_or(kPaperModes);
    t.structure_not_chosen = too_few_to_choose && !(settings.basis && settings.modes);
  } else {
    report(progress, kNoiseShare, "structure of Eq. 8");
    t.structure = choose_structure(structure_search_settings(settings, runner), junction_c,
                                   y_minus_d, progress);
    basis = t.structure->basis;
    em.modes = t.structure->modes;
    structure_fit = core::EmStartingPoint{t.structure->fit.theta, t.structure->fit.mixture};
  }

  // What the structure search fitted on: the case-log junction and its basis, kept in case the
  // final fit fails on the junction from the ranges (below).
  SmoothedJunction case_log_junction = t.junction;
  const Eigen::VectorXd case_log_junction_c = junction_c;
  const core::Basis case_log_basis = basis;
  if (settings.junction_source != JunctionSource::CaseLog && t.thermal.map && !too_few_to_choose) {
    report(progress, kSearchShare, "junction dynamics from the ranges");
    const std::optional<core::ThermalNoise> held_noise =
        t.kalman_noise_fit ? held_junction_noise(*t.kalman_noise_fit) : std::nullopt;
    t.junction_dynamics = complete_junction(fit_data, settings, *t.thermal.map, noise, held_noise,
                                            junction_c, basis, em, structure_fit);
    if (settings.junction_source == JunctionSource::Ranges) {
      t.junction_dynamics->take_ranges_answer();
    }
    if (t.junction_dynamics->replaced) {
      t.thermal_parameters = with_junction_dynamics(t.thermal_parameters,
                                                    t.junction_dynamics->best.dynamics);
      noise = t.junction_dynamics->chosen_noise();
      t.junction = junction_at_ranges(data, t.thermal_parameters, noise,
                                      settings.thermal.ambient_fallback_c);
      junction_c = at_fitted_ranges(t.junction.junction_c);
      basis = basis_spanning(basis, junction_c);
    }
  }

  report(progress, kJunctionShare, "EM training");
  const auto final_fit = [&] {
    const Eigen::MatrixXd h = basis.design_matrix(junction_c);
    // The final fit starts where the search's (looser) fit of the chosen candidate ended, unless
    // the paper's start (Eq. 20) or M-step (Eq. 19 as printed) is asked for, to reproduce them.
    // θ's coordinates change with the basis's rescaling when the junction was replaced: then θ
    // starts at least squares.
    core::EmTrainOptions options = em;
    if (structure_fit && options.initialization == core::EmInitialization::Quantiles &&
        options.m_step == core::MStep::Exact) {
      // (A structure chosen before, on other ranges, is rescaled to this junction too.)
      const bool rescaled =
          (t.junction_dynamics && t.junction_dynamics->replaced) || settings.structure_chosen;
      options.start =
          rescaled ? least_squares_start(h, y_minus_d, structure_fit->mixture) : *structure_fit;
    }
    if (t.structure) {
      // The search's fits stop earlier than this one: a mode they kept may empty here, and then
      // the data show fewer modes than the search counted, not a reason to refuse them.
      FinalFit fit = train_em_dropping_emptied_modes(h, y_minus_d, options);
      t.em = std::move(fit.em);
      t.final_fit_dropped_modes = std::move(fit.dropped_modes);
    } else {
      t.em = core::train_em(h, y_minus_d, options);  // a structure given is the user's to answer for
    }
  };
  try {
    final_fit();
  } catch (const core::NumericalError& e) {
    if (!(t.junction_dynamics && t.junction_dynamics->replaced)) throw;
    // The structure was chosen on the case-log junction; on the junction from the ranges its
    // basis can be singular (a high order over the other span). The case-log junction, on which
    // the search fitted it, stays rather than the data being refused.
    t.junction_dynamics->replaced = false;
    t.junction_dynamics->replaced_untested = false;
    t.junction_dynamics->refused_by_final_fit = e.what();
    t.thermal_parameters = t.thermal.identified();
    noise = t.junction_dynamics->chosen_noise();
    t.junction = std::move(case_log_junction);
    junction_c = case_log_junction_c;
    basis = case_log_basis;
    final_fit();
  }

  core::Calibration& c = t.calibration;
  c.thermal = t.thermal_parameters;
  c.kalman_noise = noise;
  // The daemon has no ambient sensor: its filter runs at this ambient, so where the data log one
  // it is theirs (offline the logged ambient is used at every instant, and a calibration at a
  // fallback of 22 °C put the daemon's junction R1/R2 × the difference off: 1.4 K, about 1.5 mm
  // of d̂, on a blind record logged at 26.9 °C).
  c.ambient_c = data.median_ambient_at_ranges(settings.thermal.ambient_fallback_c);
  c.model.basis = basis;
  c.model.theta = t.em.theta;
  c.model.mixture = t.em.mixture;
  c.model.trained_junction_c = core::TemperatureRange{junction_c.minCoeff(), junction_c.maxCoeff()};
  if (has_gross_errors) {
    const Eigen::VectorXd residual_mm = data.range_mm - data.true_range_mm -
                                        basis.design_matrix(t.junction.junction_c) * c.model.theta;
    c.extension = gross_error_extension(c.model.mixture, t.gross_errors.share(), residual_mm);
  }
  c.provenance.data_set = data.source;
  c.provenance.created_utc = io::utc_now();
  c.provenance.software_version = std::string("tofcomp ") + io::kVersion;
  c.provenance.samples = static_cast<long>(data.range_mm.size());
  c.provenance.notes = "beam " + std::to_string(data.beam) + "; EM " +
                       std::to_string(t.em.iterations) + " iterations" +
                       (t.em.converged ? "" : " (iteration cap reached)");
  for (const std::string& dropped : t.final_fit_dropped_modes) {
    c.provenance.notes += "; the final fit dropped " + dropped;
  }
  if (has_gross_errors) c.provenance.notes += "; " + gross_errors_note(t.gross_errors);
  c.choices = record_choices(t, settings.structure_chosen.has_value());
  report(progress, 1.0, "done");
  return t;
}

TrainingProgress progress_part(const TrainingProgress& progress, double from, double span,
                               const std::string& prefix) {
  if (!progress) return {};
  return [progress, from, span, prefix](double share, const std::string& stage) {
    progress(from + span * share, prefix + stage);
  };
}

core::StructureChoice choose_structure_on(const MeasuredData& data, const TrainSettings& settings,
                                          const Training& trained,
                                          const Eigen::Ref<const Eigen::VectorXd>& offset_mm,
                                          const TrainingProgress& progress) {
  core::require_same_length(data.range_mm.size(), "ranges", offset_mm.size(), "offset");
  core::require_same_length(data.range_mm.size(), "ranges", trained.junction.junction_c.size(),
                            "junction temperatures");
  if (settings.basis && settings.modes) {
    throw core::InvalidInput("the basis and the modes are given: training does not choose them");
  }
  const std::vector<Eigen::Index>& fitted = trained.gross_errors.kept;
  const bool all = trained.gross_errors.count == 0;
  const auto at_fitted = [&](const Eigen::VectorXd& v) -> Eigen::VectorXd {
    return all ? v : Eigen::VectorXd(v(fitted));
  };
  const Eigen::VectorXd y_minus_d = at_fitted(data.range_mm - data.true_range_mm - offset_mm);
  if (y_minus_d.size() < core::minimum_ranges_for_search(settings.search)) {
    throw core::InvalidInput("too few ranges to choose the structure of Eq. 8 on");
  }
  return choose_structure(structure_search_settings(settings, parallel_runner(settings.threads)),
                          at_fitted(trained.junction.junction_c), y_minus_d, progress);
}

}  // namespace tofcomp::calibration
