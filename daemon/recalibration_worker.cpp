#include "daemon/recalibration_worker.hpp"

#include <string>
#include <utility>
#include <vector>

#include "calibration/measured_data_reader.hpp"
#include "calibration/training.hpp"
#include "core/error.hpp"
#include "io/calibration_file.hpp"
#include "io/datasheet_file.hpp"

namespace tofcomp::daemon {

RecalibrationWorker::~RecalibrationWorker() {
  join();
}

void RecalibrationWorker::join() {
  if (thread_.joinable()) thread_.join();
}

void RecalibrationWorker::start(Job job) {
  running_ = true;
  thread_ = std::thread([this, job = std::move(job)] {
    Outcome outcome;
    outcome.file = job.output;
    try {
      if (job.output.empty()) throw core::Error("no calibration file to write (calibration.file)");
      std::vector<std::string> warnings;
      const calibration::MeasuredData measured =
          calibration::read_measured_data(job.data.string(), job.beam, warnings);
      calibration::TrainSettings settings;
      settings.thermal.datasheet = io::read_datasheet_file(job.datasheet.string());
      const calibration::Training trained = calibration::train_calibration(measured, settings);
      io::write_calibration_file(job.output.string(), trained.calibration);
      outcome.calibration = std::make_shared<const core::Calibration>(trained.calibration);
    } catch (const std::exception& e) {
      outcome.error = e.what();
    }
    std::lock_guard lock(outcome_mutex_);
    outcome_ = std::move(outcome);
  });
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
