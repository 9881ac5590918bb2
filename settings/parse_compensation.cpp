// Readers of the `calibration` section (the calibration file and overrides of its noise levels)
// and the `compensation` section (the sliding-window EM estimate of §6 per beam).
#include <string>

#include "io/yaml_typed_fields.hpp"
#include "settings/section_parsers.hpp"

namespace tofcomp::settings::sections {

namespace {

using io::fields::at_least;
using io::fields::between;
using io::fields::greater_than;
using io::fields::greater_than_up_to;

}  // namespace

void parse_calibration(const io::YamlMap& root, const ParseContext& context,
                       CalibrationConfig& out) {
  const auto calibration = io::fields::section(root, "calibration", {"file", "noise", "ambient_c"});
  if (!calibration) return;
  out.file = io::fields::required_path(*calibration, "file", context.base_directory);
  if (const auto noise = io::fields::section(
          *calibration, "noise",
          {"process_noise_case_k2_per_s", "process_noise_junction_k2_per_s", "sensor_noise_k2"})) {
    out.kalman_noise.case_process_psd_k2_per_s =
        io::fields::optional_number(*noise, "process_noise_case_k2_per_s", at_least(0));
    out.kalman_noise.junction_process_psd_k2_per_s =
        io::fields::optional_number(*noise, "process_noise_junction_k2_per_s", at_least(0));
    out.kalman_noise.measurement_variance_k2 =
        io::fields::optional_number(*noise, "sensor_noise_k2", greater_than(0));
  }
  out.ambient_c = io::fields::optional_number(*calibration, "ambient_c", between(-60, 100));
}

void parse_compensation(const io::YamlMap& root, CompensationConfig& out) {
  const auto compensation =
      io::fields::section(root, "compensation", {"window", "min_samples", "change_detector", "em"});
  if (!compensation) return;
  core::SlidingWindowOptions& w = out.window;
  w.window = io::fields::integer(*compensation, "window", between(2, 100000), w.window);
  w.min_samples = io::fields::integer(*compensation, "min_samples", between(1, 100000), w.min_samples);
  if (const auto change =
          io::fields::section(*compensation, "change_detector", {"drift", "threshold"})) {
    w.change.drift = io::fields::number(*change, "drift", between(0, 100), w.change.drift);
    w.change.threshold =
        io::fields::number(*change, "threshold", greater_than_up_to(0, 1e6), w.change.threshold);
  }
  w.method = core::WindowEm::Incremental;  // the daemon's default (docs/daemon.md)
  if (const auto em =
          io::fields::section(*compensation, "em",
                          {"method", "refreshes", "tolerance_mm", "max_iterations", "m_step"})) {
    w.method = io::fields::choice<core::WindowEm>(
        *em, "method",
        {{"incremental", core::WindowEm::Incremental}, {"exact", core::WindowEm::Exact}}, w.method);
    w.refreshes =
        static_cast<int>(io::fields::integer(*em, "refreshes", between(0, 100000), w.refreshes));
    w.em.distance_tolerance =
        io::fields::number(*em, "tolerance_mm", greater_than_up_to(0, 1000), w.em.distance_tolerance);
    w.em.max_iterations = static_cast<int>(
        io::fields::integer(*em, "max_iterations", between(1, 10000), w.em.max_iterations));
    w.em.m_step = io::fields::choice<core::MStep>(
        *em, "m_step", {{"exact", core::MStep::Exact}, {"paper", core::MStep::PaperAsPrinted}},
        w.em.m_step);
  }
}

}  // namespace tofcomp::settings::sections
