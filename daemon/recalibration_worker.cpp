#include "daemon/recalibration_worker.hpp"

#include <fmt/format.h>

#include <string>
#include <utility>

#include "calibration/plausibility.hpp"
#include "core/error.hpp"
#include "core/printable_text.hpp"
#include "io/calibration_file.hpp"

namespace tofcomp::daemon {

namespace {

std::string joined(const std::vector<std::string>& parts) {
  std::string text;
  for (const auto& p : parts) text += (text.empty() ? "" : "; ") + p;
  return text;
}

}  // namespace

RecalibrationWorker::~RecalibrationWorker() {
  stop();
}

void RecalibrationWorker::stop() {
  process_.cancel();
  if (thread_.joinable()) thread_.join();
}

void RecalibrationWorker::start(Job job) {
  running_ = true;
  thread_ = std::thread([this, job = std::move(job)] {
    Outcome outcome = work(job);
    std::lock_guard lock(outcome_mutex_);
    outcome_ = std::move(outcome);
  });
}

// The training child, then the gate, then the file (docs/daemon.md, "Recalibration").
RecalibrationWorker::Outcome RecalibrationWorker::work(const Job& job) {
  Outcome outcome;
  outcome.file = job.output;
  try {
    if (job.output.empty()) throw core::Error("no calibration file to write (calibration.file)");
    TrainingRequest request;
    request.recording = &job.recording;
    request.source = core::printable(job.recording.path().string());  // a client may name it
    request.beam = job.beam;
    request.datasheet = job.datasheet;
    if (job.running) request.running_calibration = io::calibration_to_yaml(*job.running);
    request.limits = job.limits;
    request.model_search = job.model_search;
    const TrainingReport report = process_.run(request);
    auto trained = std::make_shared<core::Calibration>(
        io::parse_calibration_yaml(report.calibration_yaml, "the trained calibration"));
    trained->provenance.data_set = job.recording.path().string();
    outcome.note = report.summary.value("note", std::string());
    std::vector<std::string> faults = calibration::implausibilities(*trained);
    const nlohmann::json& held_out = report.summary.at("held_out");
    if (!held_out.is_null()) {
      calibration::HeldOutComparison c;
      c.ranges = held_out.at("ranges").get<long>();
      c.windows = held_out.at("windows").get<long>();
      c.new_mae_mm = held_out.at("new_mae_mm").get<double>();
      c.running_mae_mm = held_out.at("running_mae_mm").get<double>();
      if (auto worse = calibration::held_out_regression(c)) faults.push_back(*worse);
      outcome.note += fmt::format("; held-out d̂ error {:.3f} mm (running calibration {:.3f} mm)",
                                  c.new_mae_mm, c.running_mae_mm);
    }
    if (!faults.empty()) {
      outcome.rejected = joined(faults);
      return outcome;
    }
    io::write_calibration_file(job.output.string(), *trained);
    outcome.calibration = std::move(trained);
  } catch (const std::exception& e) {
    outcome.error = e.what();
  }
  return outcome;
}

std::optional<RecalibrationWorker::Outcome> RecalibrationWorker::take() {
  std::optional<Outcome> outcome;
  {
    std::lock_guard lock(outcome_mutex_);
    outcome.swap(outcome_);
  }
  if (!outcome) return std::nullopt;
  thread_.join();
  running_ = false;
  return outcome;
}

}  // namespace tofcomp::daemon
