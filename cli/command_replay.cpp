// tofcomp replay RECORDING [--config tofcompd.yaml]: a tofcompd recording through the daemon's
// compensation path (realtime/, set up as the daemon sets it up from the same configuration),
// offline. Prints, or writes as CSV, what the daemon published for each scan: the check that a
// recording reproduces the daemon's outputs, and a way to try new compensation settings on
// recorded data.
#include <fmt/format.h>

#include <cmath>
#include <fstream>

#include "cli/command.hpp"
#include "core/error.hpp"
#include "io/measured_data_csv.hpp"
#include "realtime/recording_replay.hpp"
#include "settings/daemon_config_yaml.hpp"
#include "settings/embedded_default_config.hpp"
#include "settings/pipeline_setup.hpp"

namespace tofcomp::cli {
namespace {

struct ReplayOptions {
  std::string recording;
  std::string config;
  std::string output;
};

std::string cell(double v) {
  return std::isfinite(v) ? fmt::format("{}", v) : std::string();
}

CommandResult replay(const ReplayOptions& o, const CommonOptions& common) {
  const settings::DaemonConfig config = o.config.empty() ? settings::embedded_default_config()
                                                         : settings::load_daemon_config(o.config);
  realtime::CompensationPipeline pipeline(settings::pipeline_settings(config));
  if (auto calibration = settings::read_configured_calibration(config)) {
    pipeline.set_calibration(std::move(calibration), 1);
  }
  const io::MeasurementTable table = io::read_measured_data_file(o.recording);
  for (const auto& w : table.warnings) {
    if (!common.quiet) std::fprintf(stderr, "warning: %s\n", w.c_str());
  }
  std::ofstream out;
  if (!o.output.empty()) {
    out.open(o.output);
    if (!out) throw core::Error("cannot write " + o.output);
    out << "sequence,beam,flags,raw_mm,compensated_mm,window_mm,window_std_mm,mode\n";
  }
  std::uint64_t scans = 0;
  double sum_abs_change = 0.0;
  std::uint64_t compensated = 0;
  realtime::replay_recording(table, o.recording, pipeline, [&](const ipc::CompensatedScan& s) {
    ++scans;
    for (std::size_t b = 0; b < s.beams.size(); ++b) {
      const ipc::BeamValue& v = s.beams[b];
      if (std::isfinite(v.compensated_mm)) {
        sum_abs_change += std::abs(v.compensated_mm - v.raw_mm);
        ++compensated;
      }
      if (out.is_open()) {
        out << s.sequence << ',' << b << ',' << v.flags << ',' << cell(v.raw_mm) << ','
            << cell(v.compensated_mm) << ',' << cell(v.window_mm) << ',' << cell(v.window_std_mm)
            << ',' << static_cast<int>(v.most_probable_mode) << '\n';
      }
    }
  });
  if (out.is_open() && !out.flush()) throw core::Error("cannot write " + o.output);
  CommandResult result;
  const double mean_change = compensated ? sum_abs_change / compensated : 0.0;
  const core::Calibration* calibration = pipeline.calibration();
  const bool extended = calibration && calibration->extension;
  const std::string extension = extended ? calibration->extension->name() : "";
  result.json = {{"recording", o.recording},
                 {"config", config.source},
                 {"extension", extended ? nlohmann::json(extension) : nlohmann::json(nullptr)},
                 {"scans", scans},
                 {"ranges_compensated", compensated},
                 {"mean_abs_correction_mm", mean_change}};
  if (!o.output.empty()) result.json["output"] = o.output;
  result.text = fmt::format(
      "replayed {} scans of {} through the compensation path of {}{}\n"
      "{} ranges compensated, mean |correction| {:.3f} mm\n{}",
      scans, o.recording, config.source,
      extended ? " (calibration with the " + extension + " extension)" : "", compensated,
      mean_change, o.output.empty() ? "" : "wrote " + o.output + "\n");
  return result;
}

}  // namespace

void register_replay(CLI::App& app, const CommonOptions& common, CommandRunner& run) {
  auto* cmd = app.add_subcommand(
      "replay", "Replay a tofcompd recording through the daemon's compensation path");
  auto o = std::make_shared<ReplayOptions>();
  cmd->add_option("recording", o->recording, "A recording written by tofcompd (interchange CSV)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--config", o->config,
                  "The daemon's configuration (compensation settings, calibration); default: "
                  "the built-in one")
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", o->output,
                  "Write every beam of every scan as CSV (sequence, beam, flags, raw, "
                  "compensated, window, window std, mode)");
  cmd->callback([&common, &run, o] { run = [&common, o] { return replay(*o, common); }; });
}

}  // namespace tofcomp::cli
