// tofcomp replay RECORDING [--config tofcompd.yaml] [--calibration C.yaml]: a tofcompd recording,
// or any measured data, through the daemon's compensation path (realtime/, set up as the daemon
// sets it up from the same configuration), offline. Prints, or writes as CSV, what the daemon
// published for each range: the check that a recording reproduces the daemon's outputs, a way to
// try new compensation settings on recorded data, and with the still surfaces of each beam
// (calibration/still_surfaces.hpp) the interchange a field test scores.
#include <fmt/format.h>

#include <cmath>
#include <fstream>

#include "calibration/still_surfaces.hpp"
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
  std::string calibration;
  std::string output;
};

// One range as the path published it.
struct ReplayedRange {
  double time_s = 0.0;
  std::size_t beam = 0;
  double range_mm = 0.0;
  ipc::BeamValue value;
  std::uint64_t sequence = 0;
};

// Per range: 1 when it lies on a still surface of its beam, 0 when set apart; empty without a
// calibration (the gate comes from its modes).
std::vector<std::string> still_column(const std::vector<ReplayedRange>& ranges,
                                      const core::Calibration* calibration) {
  std::vector<std::string> still(ranges.size());
  if (calibration == nullptr) return still;
  std::vector<std::vector<std::size_t>> by_beam;
  for (std::size_t i = 0; i < ranges.size(); ++i) {
    if (ranges[i].beam >= by_beam.size()) by_beam.resize(ranges[i].beam + 1);
    by_beam[ranges[i].beam].push_back(i);
  }
  for (const auto& rows : by_beam) {
    if (rows.empty()) continue;
    Eigen::VectorXd t(static_cast<Eigen::Index>(rows.size()));
    Eigen::VectorXd y(t.size());
    for (std::size_t j = 0; j < rows.size(); ++j) {
      t[static_cast<Eigen::Index>(j)] = ranges[rows[j]].time_s;
      y[static_cast<Eigen::Index>(j)] = ranges[rows[j]].range_mm;
    }
    const core::StillSegmentation s =
        calibration::still_surfaces(t, y, calibration->model.mixture, {});
    for (std::size_t j = 0; j < rows.size(); ++j) {
      still[rows[j]] = s.episode[j] == core::kSetApart ? "0" : "1";
    }
  }
  return still;
}

std::string cell(double v) {
  return std::isfinite(v) ? fmt::format("{}", v) : std::string();
}

CommandResult replay(const ReplayOptions& o, const CommonOptions& common) {
  settings::DaemonConfig config = o.config.empty() ? settings::embedded_default_config()
                                                   : settings::load_daemon_config(o.config);
  if (!o.calibration.empty()) config.calibration.file = o.calibration;
  realtime::CompensationPipeline pipeline(settings::pipeline_settings(config));
  if (auto calibration = settings::read_configured_calibration(config)) {
    pipeline.set_calibration(std::move(calibration), 1);
  }
  const io::MeasurementTable table = io::read_measured_data_file(o.recording);
  for (const auto& w : table.warnings) {
    if (!common.quiet) std::fprintf(stderr, "warning: %s\n", w.c_str());
  }
  std::uint64_t scans = 0;
  double sum_abs_change = 0.0;
  std::uint64_t compensated = 0;
  std::vector<ReplayedRange> ranges;
  realtime::replay_recording(table, o.recording, pipeline,
                             [&](const realtime::RawScan& in, const ipc::CompensatedScan& s) {
                               ++scans;
                               for (std::size_t b = 0; b < s.beams.size(); ++b) {
                                 if (in.no_echo[b])
                                   continue;  // no row of the data gave this beam a range
                                 const ipc::BeamValue& v = s.beams[b];
                                 if (std::isfinite(v.compensated_mm)) {
                                   sum_abs_change += std::abs(v.compensated_mm - v.raw_mm);
                                   ++compensated;
                                 }
                                 if (!o.output.empty())
                                   ranges.push_back({in.time_s, b, in.ranges_mm[b], v, s.sequence});
                               }
                             });
  if (!o.output.empty()) {
    const std::vector<std::string> still = still_column(ranges, pipeline.calibration());
    std::ofstream out(o.output);
    if (!out) throw core::Error("cannot write " + o.output);
    out << "time_s,beam,range_mm,compensated_mm,window_mm,window_std_mm,still,flags,sequence,"
           "mode\n";
    for (std::size_t i = 0; i < ranges.size(); ++i) {
      const ReplayedRange& r = ranges[i];
      const ipc::BeamValue& v = r.value;
      out << fmt::format("{}", r.time_s) << ',' << r.beam << ',' << cell(r.range_mm) << ','
          << cell(v.compensated_mm) << ',' << cell(v.window_mm) << ',' << cell(v.window_std_mm)
          << ',' << still[i] << ',' << v.flags << ',' << r.sequence << ','
          << static_cast<int>(v.most_probable_mode) << '\n';
    }
    if (!out.flush()) throw core::Error("cannot write " + o.output);
  }
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
      "replay",
      "Replay a tofcompd recording, or any measured data, through the daemon's compensation path");
  auto o = std::make_shared<ReplayOptions>();
  cmd->add_option("recording", o->recording, "A recording written by tofcompd (interchange CSV)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--config", o->config,
                  "The daemon's configuration (compensation settings, calibration); default: "
                  "the built-in one")
      ->check(CLI::ExistingFile);
  cmd->add_option("--calibration", o->calibration,
                  "Calibration file to compensate with, in place of the configuration's")
      ->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", o->output,
                  "Write every range as CSV: time_s, beam, range_mm, compensated_mm, window_mm, "
                  "window_std_mm, still (1 on a still surface of its beam, 0 set apart; empty "
                  "without a calibration), flags, sequence, mode")
      ->type_name("FILE");
  cmd->callback([&common, &run, o] { run = [&common, o] { return replay(*o, common); }; });
}

}  // namespace tofcomp::cli
