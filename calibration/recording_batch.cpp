#include "calibration/recording_batch.hpp"

#include <algorithm>
#include <chrono>
#include <exception>
#include <mutex>
#include <new>
#include <system_error>

#include <fmt/format.h>

#include "calibration/measured_data_reader.hpp"
#include "calibration/parallel_for.hpp"
#include "core/error.hpp"

namespace tofcomp::calibration {

std::vector<std::filesystem::path> recordings_in(const std::filesystem::path& directory) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(directory, ec)) {
    throw core::InvalidInput(fmt::format("{}: not a directory", directory.string()));
  }
  std::vector<fs::path> found;
  fs::directory_iterator it(directory, ec);
  if (ec) throw core::InvalidInput(fmt::format("{}: cannot list: {}", directory.string(), ec.message()));
  for (const fs::directory_iterator end; it != end; it.increment(ec)) {
    if (ec) break;
    const fs::path& path = it->path();
    std::error_code type_ec;
    if (path.extension() != kRecordingExtension || !it->is_regular_file(type_ec)) continue;
    if (found.size() == kMaxBatchRecordings) {
      throw core::InvalidInput(fmt::format("{}: more than {} recordings (*{}); split the directory",
                                           directory.string(), kMaxBatchRecordings,
                                           kRecordingExtension));
    }
    found.push_back(path);
  }
  if (ec) throw core::InvalidInput(fmt::format("{}: cannot list: {}", directory.string(), ec.message()));
  if (found.empty()) {
    throw core::InvalidInput(
        fmt::format("{}: no recording (*{}) in it", directory.string(), kRecordingExtension));
  }
  std::sort(found.begin(), found.end());
  return found;
}

const core::Calibration& RecordingOutcome::calibration() const {
  if (!training) throw core::Error(recording.string() + ": not calibrated: " + error);
  return calibration_to_deploy(training->calibration, search ? &*search : nullptr);
}

namespace {

// One recording, start to end; every failure is kept in the outcome, none escapes.
RecordingOutcome calibrate_one(const std::filesystem::path& recording, const BatchSettings& settings,
                               int threads) {
  const auto start = std::chrono::steady_clock::now();
  RecordingOutcome out;
  out.recording = recording;
  try {
    const MeasuredData data = read_measured_data(recording.string(), settings.beam, out.warnings);
    data.require_true_ranges();
    TrainSettings training = settings.training;
    training.threads = threads;
    out.training = train_calibration(data, training);
    ModelSearchOptions search = settings.search;
    search.threads = threads;
    try {
      TrainedSearch trained = search_and_recheck(data, training, search, *out.training);
      out.training = std::move(trained.training);
      out.search = std::move(trained.search);
      out.junction_recheck = std::move(trained.junction_recheck);
      out.structure_recheck = std::move(trained.structure_recheck);
    } catch (const core::Error& e) {
      out.search_error = e.what();
    }
  } catch (const core::Error& e) {
    out.error = e.what();
  } catch (const std::bad_alloc&) {
    out.error = "out of memory";
  } catch (const std::exception& e) {
    out.error = std::string("internal error: ") + e.what();
  }
  if (!out.training && out.error.empty()) out.error = "not calibrated";
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace

void calibrate_recordings(const std::vector<std::filesystem::path>& recordings,
                          const BatchSettings& settings, const RecordingStarted& started,
                          const RecordingFinished& finished) {
  if (recordings.empty()) return;
  const int threads = thread_count(settings.jobs);
  const int at_once = std::min<int>(threads, static_cast<int>(recordings.size()));
  // The cores left over when there are fewer recordings than threads go to their searches.
  const int per_recording = std::max(1, threads / at_once);
  std::mutex report_mutex;
  parallel_for(static_cast<int>(recordings.size()), at_once, [&](int i) {
    const auto index = static_cast<std::size_t>(i);
    if (started) {
      const std::lock_guard<std::mutex> lock(report_mutex);
      started(index);
    }
    RecordingOutcome outcome = calibrate_one(recordings[index], settings, per_recording);
    if (finished) {
      const std::lock_guard<std::mutex> lock(report_mutex);
      finished(index, std::move(outcome));
    }
  });
}

}  // namespace tofcomp::calibration
