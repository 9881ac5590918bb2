// The training child's main: see training_child.hpp.
#include "daemon/training_child.hpp"

#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <ext/stdio_filebuf.h>
#include <istream>
#include <map>
#include <new>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>

#include "calibration/held_out_training.hpp"
#include "calibration/measured_data_reader.hpp"
#include "io/calibration_file.hpp"
#include "io/bundled_datasheet.hpp"
#include "io/measured_data_csv.hpp"

namespace tofcomp::daemon {

namespace {

// Processor time allowed beyond the wall-clock limit the daemon enforces: a backstop only.
constexpr rlim_t kCpuGraceS = 10;
constexpr int kLowestPriority = 19;  // nice

constexpr int kExitFailed = 1;
constexpr int kExitUsage = 2;
constexpr int kExitMemory = 3;

int usage(const std::string& why) {
  std::fprintf(stderr, "tofcompd --train-worker: %s (it is started by tofcompd itself)\n",
               why.c_str());
  return kExitUsage;
}

// Dies with the daemon; cannot take more memory or processor time than allowed.
void limit_self(pid_t parent, rlim_t memory_bytes, rlim_t time_s) {
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (::getppid() != parent) {  // the daemon died before prctl, or this was started by hand
    std::fprintf(stderr, "tofcompd --train-worker: its parent is not tofcompd (pid %d)\n",
                 static_cast<int>(parent));
    std::_Exit(kExitFailed);
  }
  const rlimit memory{memory_bytes, memory_bytes};
  ::setrlimit(RLIMIT_AS, &memory);
  const rlimit cpu{time_s + kCpuGraceS, time_s + kCpuGraceS};
  ::setrlimit(RLIMIT_CPU, &cpu);
  const rlimit no_core{0, 0};
  ::setrlimit(RLIMIT_CORE, &no_core);
  // Training gives way to the daemon's scans: at the lowest priority (nice 19) the scheduler runs
  // the daemon's threads first whenever they wake, while training still progresses on a busy
  // machine. Where a policy forbids it, it runs as it is.
  ::setpriority(PRIO_PROCESS, 0, kLowestPriority);
}

std::string read_fd(int fd) {
  std::string text;
  char buffer[1 << 16];
  for (ssize_t n; (n = ::read(fd, buffer, sizeof buffer)) > 0;) {
    text.append(buffer, static_cast<std::size_t>(n));
  }
  return text;
}

nlohmann::json report(const calibration::HeldOutTraining& trained) {
  nlohmann::json held_out = nullptr;
  if (trained.comparison) {
    const calibration::HeldOutComparison& c = *trained.comparison;
    held_out = {{"ranges", c.ranges},
                {"windows", c.windows},
                {"new_mae_mm", c.new_mae_mm},
                {"running_mae_mm", c.running_mae_mm}};
  }
  return {{"calibration", io::calibration_to_yaml(trained.training.calibration)},
          {"trained_ranges", trained.training.calibration.provenance.samples},
          {"note", trained.note},
          {"kept_terms", trained.kept_terms},
          {"held_out", held_out}};
}

}  // namespace

int training_child_main(int argc, char** argv) {
  std::map<std::string, std::string> options;
  bool has_running = false;
  bool model_search = false;
  for (int i = 2; i < argc; ++i) {
    const std::string key = argv[i];
    if (key == "--running-calibration-on-fd-3") {
      has_running = true;
    } else if (key == "--model-search") {
      model_search = true;
    } else if (key.starts_with("--") && i + 1 < argc) {
      options[key] = argv[++i];
    } else {
      return usage("unexpected argument '" + key + "'");
    }
  }
  for (const char* key :
       {"--source", "--beam", "--datasheet", "--memory-bytes", "--time-s", "--parent-pid"}) {
    if (!options.contains(key)) return usage(std::string("missing ") + key);
  }
  const std::string& memory = options["--memory-bytes"];
  try {
    limit_self(static_cast<pid_t>(std::stol(options["--parent-pid"])),
               static_cast<rlim_t>(std::stoull(memory)),
               static_cast<rlim_t>(std::stoull(options["--time-s"])));
    const std::string& source = options["--source"];
    const int beam = std::stoi(options["--beam"]);
    __gnu_cxx::stdio_filebuf<char> input(STDIN_FILENO, std::ios::in);
    std::istream in(&input);
    const io::MeasurementTable table = io::read_measured_data(in, source);
    const calibration::MeasuredData data =
        calibration::measured_data_from_table(table, source, beam);
    std::optional<core::Calibration> running;
    if (has_running) {
      running =
          io::parse_calibration_yaml(read_fd(kRunningCalibrationFd), "the running calibration");
    }
    calibration::TrainSettings settings;
    // An empty --datasheet: recalibration.datasheet left out, the built-in LMS 200's.
    settings.thermal.datasheet = io::datasheet_or_bundled(options["--datasheet"]);
    // A recording logs no ambient (the daemon has no sensor for it): the ambient the running
    // calibration holds stays the one the new calibration carries.
    if (running) settings.thermal.ambient_fallback_c = running->ambient_c;
    const calibration::ModelSearchOptions search;  // the defaults of tofcomp diagnose
    const calibration::HeldOutTraining trained = calibration::train_with_held_out(
        data, settings, running ? &*running : nullptr, model_search ? &search : nullptr);
    // A file name need not be UTF-8: such bytes are replaced rather than fail the report.
    const std::string text =
        report(trained).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
    if (std::fwrite(text.data(), 1, text.size(), stdout) != text.size() ||
        std::fflush(stdout) != 0) {
      std::fprintf(stderr, "cannot write the report\n");
      return kExitFailed;
    }
    return 0;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr,
                 "training needed more memory than the %s bytes of "
                 "recalibration.limits.memory_mib\n",
                 memory.c_str());
    return kExitMemory;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return kExitFailed;
  }
}

}  // namespace tofcomp::daemon
