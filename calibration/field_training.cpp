// Training in the field: see field_training.hpp.
#include "calibration/field_training.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "calibration/beam_scores.hpp"
#include "calibration/junction_estimate.hpp"
#include "calibration/measured_data_reader.hpp"
#include "calibration/still_surfaces.hpp"
#include "calibration/thermal_fit.hpp"
#include "core/kalman_noise_fit.hpp"
#include "core/lms200_limits.hpp"
#include "core/error.hpp"
#include "io/utc_time.hpp"
#include "io/version.hpp"

namespace tofcomp::calibration {
namespace {

// The share of the progress the per-beam stage (junction, still episodes) takes; the fit the rest.
constexpr double kBeamsShare = 0.4;

// The ranges the fit takes, gathered over every beam of every record.
struct FieldRanges {
  std::vector<double> time_s;
  std::vector<double> junction_c;
  std::vector<double> y;  // the range, or the range less its known distance
  std::vector<int> episode;
  int episodes = 0;
  long with_reference = 0;
};

// One beam: its junction temperatures, its ranges of known distance, its still episodes.
BeamStillness gather_beam(const MeasuredData& data, const core::Calibration& bench,
                          const core::StillEpisodeOptions& still, RecordJunctions& junctions,
                          FieldRanges& out) {
  BeamStillness b;
  b.source = data.source;
  b.beam = data.beam;
  b.ranges = static_cast<long>(data.range_mm.size());
  if (data.range_mm.size() == 0) return b;
  const SmoothedJunction& junction = junctions.at(data);
  std::vector<Eigen::Index> unknown;
  for (Eigen::Index k = 0; k < data.range_mm.size(); ++k) {
    if (data.has_true_range[static_cast<std::size_t>(k)]) {
      out.time_s.push_back(data.range_time_s[k]);
      out.junction_c.push_back(junction.junction_c[k]);
      out.y.push_back(data.range_mm[k] - data.true_range_mm[k]);
      out.episode.push_back(core::kKnownDistance);
      ++b.with_reference;
    } else {
      unknown.push_back(k);
    }
  }
  out.with_reference += b.with_reference;
  if (unknown.empty()) return b;
  const Eigen::VectorXd time_s = data.range_time_s(unknown);
  const Eigen::VectorXd range_mm = data.range_mm(unknown);
  const core::StillSegmentation s = still_surfaces(time_s, range_mm, bench.model.mixture, still);
  b.episodes = static_cast<long>(s.episodes.size());
  for (std::size_t i = 0; i < unknown.size(); ++i) {
    const int e = s.episode[i];
    if (e == core::kSetApart) {
      ++b.set_apart;
      continue;
    }
    const Eigen::Index k = unknown[i];
    out.time_s.push_back(data.range_time_s[k]);
    out.junction_c.push_back(junction.junction_c[k]);
    out.y.push_back(data.range_mm[k]);
    out.episode.push_back(out.episodes + e);
    ++b.still;
  }
  out.episodes += static_cast<int>(b.episodes);
  return b;
}

// Shifts the constant so that the field bias H(t)θ + Σπμ equals the bench calibration's over the
// bench's junction band: the modes' means move by c and the distances by −c (the fit's one free
// direction, core/field_em.hpp). Returns c.
double match_bench_band(const core::Calibration& bench, const core::Basis& basis,
                        core::FieldEmResult& em) {
  const core::TemperatureRange band = *bench.model.trained_junction_c;
  const Eigen::VectorXd t = Eigen::VectorXd::LinSpaced(kBandMatchPoints, band.min_c, band.max_c);
  const Eigen::VectorXd bench_bias =
      bench.model.bias(t).array() + bench.model.mixture.mean_offset();
  const Eigen::VectorXd field_bias =
      (basis.design_matrix(t) * em.theta).array() + em.mixture.mean_offset();
  const double shift = (bench_bias - field_bias).mean();
  em.mixture.mean.array() += shift;
  em.episode_distance.array() -= shift;
  return shift;
}

std::string sources_of(const std::vector<FieldRecord>& records) {
  std::string joined;
  for (const auto& r : records) joined += (joined.empty() ? "" : ", ") + r.source;
  return joined;
}

// Without a bench calibration, what one would give: the thermal network fitted to the case log
// of the record with the most readings (§3.2 with the datasheet's prior) and the Kalman noise
// from it, the ambient that record logged, a Legendre bias (its order chosen on the data), and
// the paper's two modes as the datasheet describes the device's spread: at ±kSystematicErrorMm / 2
// with its statistical error, for the still gate alone (EM starts from the data).
core::Calibration starting_calibration(const std::vector<FieldRecord>& records,
                                       const ThermalFitSettings& thermal) {
  const FieldRecord* longest = nullptr;
  std::size_t most = 0;
  for (const FieldRecord& r : records) {
    const std::size_t readings = static_cast<std::size_t>(std::count_if(
        r.table.rows.begin(), r.table.rows.end(),
        [](const io::MeasurementRow& row) { return row.case_temp_c.has_value(); }));
    if (readings > most) {
      most = readings;
      longest = &r;
    }
  }
  if (longest == nullptr) {
    throw core::InvalidInput("field training without a bench calibration fits the thermal "
                             "network to the case log, and no record has case_temp_c readings");
  }
  const std::vector<int> beams = beams_with_ranges(longest->table);
  const MeasuredData data = measured_data_from_table(longest->table, longest->source,
                                                     beams.empty() ? 0 : beams.front());
  core::Calibration c;
  c.thermal = fit_thermal(data, nullptr, thermal).identified();
  c.kalman_noise =
      core::fit_kalman_noise(case_log(data, thermal.ambient_fallback_c), c.thermal, {}).noise;
  c.ambient_c = data.median_ambient_at_ranges(thermal.ambient_fallback_c);
  c.model.basis = core::Basis({core::BasisTerm{}}, core::TemperatureScaling{});
  c.model.theta = Eigen::VectorXd::Zero(1);
  const double offset = core::lms200::kSystematicErrorMm / 2.0;
  const double variance = core::lms200::kStatisticalErrorMm * core::lms200::kStatisticalErrorMm;
  c.model.mixture.mean = Eigen::Vector2d(-offset, offset);
  c.model.mixture.variance = Eigen::Vector2d(variance, variance);
  c.model.mixture.weight = Eigen::Vector2d(0.5, 0.5);
  c.provenance.data_set = "the case log of " + longest->source;
  return c;
}

}  // namespace

FieldTraining train_in_field(const std::vector<FieldRecord>& records,
                             const core::Calibration* given_bench,
                             const FieldTrainSettings& settings, const FieldProgress& progress) {
  const auto report = [&](double share, const std::string& stage) {
    if (progress) progress(share, stage);
  };
  if (given_bench && !given_bench->model.trained_junction_c) {
    throw core::InvalidInput(
        "the bench calibration names no junction band (trained_junction_c): the field fit "
        "matches its constant to the bench's there");
  }
  if (!given_bench) report(0.0, "thermal fit to the case log");
  const core::Calibration bench =
      given_bench ? *given_bench : starting_calibration(records, settings.thermal);
  FieldTraining t;
  t.bench_given = given_bench != nullptr;
  core::StillEpisodeOptions still = settings.still;
  if (still.gate_mm == 0.0) still.gate_mm = still_gate_mm(bench.model.mixture);
  t.gate_mm = still.gate_mm;

  FieldRanges ranges;
  std::size_t beams_total = 0;
  std::vector<std::vector<int>> beams(records.size());
  for (std::size_t r = 0; r < records.size(); ++r) {
    beams[r] = beams_with_ranges(records[r].table);
    beams_total += beams[r].size();
  }
  std::size_t done = 0;
  for (std::size_t r = 0; r < records.size(); ++r) {
    RecordJunctions junctions(bench.thermal, bench.kalman_noise, bench.ambient_c);
    for (const int beam : beams[r]) {
      report(kBeamsShare * static_cast<double>(done++) / static_cast<double>(beams_total),
             records[r].source + ", beam " + std::to_string(beam));
      const MeasuredData data = measured_data_from_table(records[r].table, records[r].source, beam);
      t.beams.push_back(gather_beam(data, bench, still, junctions, ranges));
    }
  }
  if (ranges.episodes == 0 && ranges.with_reference == 0) {
    throw core::InvalidInput("field training: no beam of " + sources_of(records) +
                             " holds a still surface (a still episode of at least " +
                             std::to_string(static_cast<int>(still.min_episode_s)) +
                             " s within " + std::to_string(still.gate_mm) +
                             " mm of its level) and no range has a reference distance");
  }
  t.episodes = ranges.episodes;
  t.ranges_with_reference = ranges.with_reference;
  t.ranges_used = static_cast<long>(ranges.y.size());

  const auto k = static_cast<Eigen::Index>(ranges.y.size());
  const Eigen::Map<const Eigen::VectorXd> junction_c(ranges.junction_c.data(), k);
  const Eigen::Map<const Eigen::VectorXd> y(ranges.y.data(), k);
  core::FieldEmOptions options;
  options.modes = bench.model.mixture.modes();
  options.variance_floor = rounding_variance_mm2();
  options.max_iterations = settings.max_iterations;
  // From the bench's modes; without a bench, from the data (train_em's quantile start).
  if (given_bench) options.start = core::EmStartingPoint{Eigen::VectorXd(0), bench.model.mixture};
  // The basis again, over the junction temperatures the records span.
  report(kBeamsShare, "choosing the basis on held-out time blocks");
  const Eigen::Map<const Eigen::VectorXd> time_s(ranges.time_s.data(), k);
  t.basis = choose_field_basis(junction_c, y, ranges.episode, ranges.episodes, time_s, options,
                               bench.model.basis);
  const core::Basis& basis = t.basis.basis;
  const Eigen::MatrixXd h = basis.design_matrix(junction_c);
  report(kBeamsShare, "EM over " + std::to_string(k) + " ranges, " +
                          std::to_string(ranges.episodes) + " still episodes");
  t.em = core::train_field_em(h, y, ranges.episode, ranges.episodes, options);
  if (t.em.distance_determined) {
    t.constant = "pinned by " + std::to_string(ranges.with_reference) +
                 " ranges of known distance";
  } else if (!given_bench) {
    t.constant = "not determined: no range has a reference and no bench calibration was given; "
                 "the modes' mean offset is set to 0, so absolute distances carry the device's "
                 "own offset";
  } else {
    const double shift = match_bench_band(bench, basis, t.em);
    std::ostringstream words;
    words << "matched to the bench calibration's bias over its junction band "
          << bench.model.trained_junction_c->min_c << " to "
          << bench.model.trained_junction_c->max_c << " °C (shift " << shift << " mm)";
    t.constant = words.str();
  }

  core::Calibration& c = t.calibration;
  c = bench;
  c.model.basis = basis;
  c.model.theta = t.em.theta;
  c.model.mixture = t.em.mixture;
  c.model.trained_junction_c = core::TemperatureRange{junction_c.minCoeff(), junction_c.maxCoeff()};
  c.extension.reset();  // the bench's extension was fitted to the bench's bias, not this one
  c.provenance.data_set = sources_of(records);
  c.provenance.created_utc = io::utc_now();
  c.provenance.software_version = std::string("tofcomp ") + io::kVersion;
  c.provenance.samples = t.ranges_used;
  c.provenance.notes = std::string(given_bench ? "field training from the bench calibration of "
                                               : "field training, the thermal network from ") +
                       bench.provenance.data_set + ": " + std::to_string(t.episodes) +
                       " still episodes; the constant " + t.constant + "; EM " +
                       std::to_string(t.em.iterations) + " iterations" +
                       (t.em.converged ? "" : " (iteration cap reached)");
  report(1.0, "done");
  return t;
}

}  // namespace tofcomp::calibration
