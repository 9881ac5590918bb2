// The small behaviour of the configuration's value types: names of the enumerations and the
// noise overrides applied to a calibration's levels.
#include "settings/daemon_config.hpp"

namespace tofcomp::settings {

core::ThermalNoise ThermalNoiseOverrides::applied_to(core::ThermalNoise from_file) const {
  if (case_process_psd_k2_per_s) from_file.case_process_psd_k2_per_s = *case_process_psd_k2_per_s;
  if (junction_process_psd_k2_per_s) {
    from_file.junction_process_psd_k2_per_s = *junction_process_psd_k2_per_s;
  }
  if (measurement_variance_k2) from_file.measurement_variance_k2 = *measurement_variance_k2;
  return from_file;
}

std::string to_string(RecalibrationSource source) {
  switch (source) {
    case RecalibrationSource::None:
      return "none";
    case RecalibrationSource::Recording:
      return "recording";
    case RecalibrationSource::PowerCycleRun:
      return "power_cycle_run";
  }
  return "?";
}

std::string to_string(RecalibrationTrigger trigger) {
  switch (trigger) {
    case RecalibrationTrigger::OnRequest:
      return "on_request";
    case RecalibrationTrigger::AtStartIfMissing:
      return "at_start_if_missing";
  }
  return "?";
}

}  // namespace tofcomp::settings
