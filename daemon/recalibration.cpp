#include "daemon/recalibration.hpp"

#include <spdlog/spdlog.h>

#include <cmath>
#include <utility>

#include "core/error.hpp"
#include "core/printable_text.hpp"
#include "io/checked_file.hpp"

namespace tofcomp::daemon {

Recalibration::Recalibration(boost::asio::io_context& io, const RunningConfig& config,
                             PowerCycleRun::Parts parts)
    : config_(config),
      inputs_(parts.inputs),
      run_(io, config.current().power.power_switch, parts,
           [this](PowerCycleSchedule::Phase phase, const std::string& why) {
             on_run_ended(phase, why);
           }) {}

Recalibration::~Recalibration() {
  stop();
}

void Recalibration::stop() {
  worker_.stop();
  run_.drop();
}

namespace {

constexpr std::uint64_t kMib = 1u << 20;
constexpr const char* kRecordingCap = "recalibration.limits.recording_mib";

}  // namespace

io::CheckedFile Recalibration::open_configured(const std::filesystem::path& data) const {
  const settings::RecalibrationLimits& limits = config_.current().recalibration.limits;
  return io::open_checked_file(data, limits.recording_mib * kMib, "recording", kRecordingCap);
}

io::CheckedFile Recalibration::open_from_client(const std::filesystem::path& named) const {
  const settings::RecalibrationConfig& r = config_.current().recalibration;
  return io::open_checked_file_in(r.recordings_directory, named, r.limits.recording_mib * kMib,
                                  "recording", kRecordingCap, "recalibration.recording.directory");
}

void Recalibration::start_if_missing() {
  const settings::RecalibrationConfig& recalibration = config_.current().recalibration;
  if (inputs_.calibration_id() != 0 ||
      recalibration.trigger != settings::RecalibrationTrigger::AtStartIfMissing) {
    return;
  }
  if (recalibration.source == settings::RecalibrationSource::Recording) {
    try {
      start_training(open_configured(recalibration.data), 0);
    } catch (const core::Error& e) {
      state_ = std::string("failed: ") + e.what();
      spdlog::error("recalibration at start: {}", e.what());
    }
  } else if (recalibration.source == settings::RecalibrationSource::PowerCycleRun) {
    const std::string refused = start_power_cycle_run();
    if (!refused.empty()) spdlog::error("recalibration at start: {}", refused);
  }
}

socket::RecalibrationResult Recalibration::request(const nlohmann::json& args) {
  const settings::DaemonConfig& config = config_.current();
  std::optional<std::filesystem::path> named;
  for (const auto& [key, value] : args.items()) {
    if (key != "recording") {
      throw core::InvalidInput("args." + core::printable(key) +
                               ": unknown; the one argument is recording");
    }
    if (!value.is_string() || value.get<std::string>().empty()) {
      throw core::InvalidInput("args.recording: expected the path of a recording (a string)");
    }
    named = value.get<std::string>();
  }
  socket::RecalibrationResult r;
  if (worker_.running() || run_.running()) {
    r.message = "a recalibration is already running: " + state_;
    return r;
  }
  switch (config.recalibration.source) {
    case settings::RecalibrationSource::None:
      r.message = "recalibration.source is none in " + config.source +
                  ": set it to recording (and recalibration.recording.data) or power_cycle_run "
                  "to recalibrate";
      return r;
    case settings::RecalibrationSource::Recording:
      break;
    case settings::RecalibrationSource::PowerCycleRun:
      if (!args.empty()) {
        r.message =
            "args.recording applies to recalibration.source recording; the source is "
            "power_cycle_run, which records its own";
        return r;
      }
      r.message = start_power_cycle_run();
      r.accepted = r.message.empty();
      if (r.accepted) r.message = state_;
      return r;
  }
  if (!named && config.recalibration.data.empty()) {
    r.message = "no recording to train on: set recalibration.recording.data or pass args.recording";
    return r;
  }
  try {
    // Opened and checked now, so that the reply says what is wrong with it.
    start_training(named ? open_from_client(*named) : open_configured(config.recalibration.data),
                   0);
  } catch (const core::InvalidInput& e) {
    r.message = e.what();
    spdlog::warn("recalibrate refused: {}", e.what());
    return r;
  }
  r.accepted = true;
  r.message = state_;
  return r;
}

// Trains on `beam` of `data` in the worker (§3 thermal identification, §5 EM), gates and writes
// the calibration, and leaves the outcome for finish() on the loop.
void Recalibration::start_training(io::CheckedFile data, int beam) {
  const settings::DaemonConfig& config = config_.current();
  const std::filesystem::path output =
      config.recalibration.output.empty() ? config.calibration.file : config.recalibration.output;
  state_ = "training on " + core::printable(data.path().string()) + ", writing " + output.string();
  spdlog::info("recalibration: {}", state_);
  RecalibrationWorker::Job job;
  job.recording = std::move(data);
  job.beam = beam;
  job.output = output;
  job.datasheet = config.recalibration.datasheet;
  if (const core::Calibration* running = inputs_.calibration()) {
    job.running = std::make_shared<const core::Calibration>(*running);
  }
  job.limits.time = config.recalibration.limits.time;
  job.limits.memory_bytes = config.recalibration.limits.memory_mib * kMib;
  job.model_search = config.recalibration.model_search;
  worker_.start(std::move(job));
}

void Recalibration::finish() {
  const std::optional<RecalibrationWorker::Outcome> outcome = worker_.take();
  if (!outcome) return;
  if (!outcome->error.empty()) {
    state_ = "failed: " + outcome->error;
    spdlog::error("recalibration {}", state_);
    return;
  }
  if (!outcome->rejected.empty()) {
    state_ = "rejected: the new calibration was not swapped in (" + outcome->rejected +
             "); calibration " + std::to_string(inputs_.calibration_id()) + " stays";
    spdlog::error("recalibration {}", state_);
    return;
  }
  try {
    inputs_.use_calibration(outcome->calibration, outcome->file.string());
    state_ = "done: calibration " + std::to_string(inputs_.calibration_id()) + " from " +
             outcome->file.string() + " (" + outcome->note + ")";
    spdlog::info("recalibration {}", state_);
  } catch (const core::Error& e) {
    state_ = std::string("failed: ") + e.what();
    spdlog::error("recalibration {}", state_);
  }
}

void Recalibration::cancel_run() {
  if (!run_.running()) return;
  spdlog::info("power-cycle run cancelled: switching the scanner back on");
  run_.cancel();
}

void Recalibration::run_recording_failed(const std::string& why) {
  run_.recording_failed(why);
}

std::string Recalibration::start_power_cycle_run() {
  const std::string refused = run_.prepare(config_.current().recalibration.power_cycle_run);
  if (!refused.empty()) return refused;
  state_ = "power-cycle run: " + run_.describe();
  spdlog::info("recalibration: {}", state_);
  run_.start();
  return {};
}

void Recalibration::on_run_ended(PowerCycleSchedule::Phase phase, const std::string& why) {
  if (phase != PowerCycleSchedule::Phase::Finished) {
    state_ = "failed: power-cycle run: " + why;
    spdlog::error("recalibration {}", state_);
    return;
  }
  const settings::PowerCycleRunConfig& run = run_.config();
  spdlog::info("power-cycle run finished: training on {}", run.recording.string());
  try {
    start_training(open_configured(run.recording), run.training_beam());
  } catch (const core::Error& e) {
    state_ = std::string("failed: power-cycle run: ") + e.what();
    spdlog::error("recalibration {}", state_);
  }
}

nlohmann::json Recalibration::run_status() const {
  if (!run_.prepared()) return nullptr;
  const PowerCycleSchedule::Progress p = run_.progress();
  std::string phase = to_string(p.phase);
  if (p.phase == PowerCycleSchedule::Phase::Cancelled && state_.starts_with("failed")) {
    phase = "failed";  // cancelled by the daemon when the run's recording failed
  } else if (p.phase == PowerCycleSchedule::Phase::Finished) {
    phase = worker_.running()              ? "training"
            : state_.starts_with("done")   ? "done"
            : state_.starts_with("failed") ? "failed"
                                           : "finished";
  }
  const settings::PowerCycleRunConfig& run = run_.config();
  nlohmann::json s = {{"phase", phase},
                      {"cycles", p.cycles},
                      {"recording", run.recording.string()},
                      {"beams", {run.beams.first, run.beams.last}},
                      {"true_range_mm", run.true_range_mm}};
  if (run_.running()) {
    s["cycle"] = p.cycle;
    s["time_left_s"] = std::round(p.time_left_s * 10.0) / 10.0;
  }
  return s;
}

}  // namespace tofcomp::daemon
