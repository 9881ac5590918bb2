// tofcomp emulate SCENARIO: serves an emulated LMS 200 on a pseudo-terminal, driven by the
// twin, until SIGINT or SIGTERM (or --duration). The first line on stdout is the device path a
// host opens; a summary of what was served follows when it stops.
#include <signal.h>

#include <cstdio>
#include <ctime>

#include "cli/command.hpp"
#include "cli/number_checks.hpp"
#include "io/measured_data_csv.hpp"
#include "sim/lms200/emulator.hpp"
#include "sim/scenario_yaml.hpp"

namespace tofcomp::cli {

namespace {

struct EmulateOptions {
  std::string scenario;
  std::string recording;
  std::string link;
  double time_scale = 1.0;
  double fault_rate = 0.0;
  std::uint64_t fault_seed = 1;
  double duration_s = 0.0;
  bool rs232 = false;
};

// Blocks SIGINT and SIGTERM in every thread (the emulator's inherits the mask) and waits for
// one, or for the duration when positive.
class StopSignal {
 public:
  StopSignal() {
    sigemptyset(&set_);
    sigaddset(&set_, SIGINT);
    sigaddset(&set_, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &set_, nullptr);
  }
  void wait(double duration_s) {
    if (duration_s > 0.0) {
      timespec t{static_cast<time_t>(duration_s),
                 static_cast<long>(
                     (duration_s - static_cast<double>(static_cast<time_t>(duration_s))) * 1e9)};
      sigtimedwait(&set_, nullptr, &t);
    } else {
      int signal = 0;
      sigwait(&set_, &signal);
    }
  }

 private:
  sigset_t set_{};
};

CommandResult emulate(const EmulateOptions& o, const CommonOptions& common) {
  sim::lms200::EmulatorSettings settings;
  settings.scenario = sim::load_scenario_file(o.scenario);
  settings.time_scale = o.time_scale;
  settings.faults = sim::lms200::FaultRates::evenly(o.fault_rate);
  settings.fault_seed = o.fault_seed;
  settings.link = o.link;
  settings.identity.supports_500k = !o.rs232;
  if (!o.recording.empty()) {
    settings.recording = io::read_measured_data_file(o.recording);
    settings.recording_source = o.recording;
  }
  StopSignal stop;
  sim::lms200::Emulator emulator(settings);
  emulator.start();
  std::printf("%s\n", emulator.device_path().c_str());
  std::fflush(stdout);
  if (!common.quiet) {
    std::fprintf(stderr,
                 "emulate: LMS 200 on %s, scenario %s at %gx real time%s; stop with Ctrl-C\n",
                 emulator.device_path().c_str(), settings.scenario.name.c_str(), o.time_scale,
                 o.fault_rate > 0.0 ? ", with injected faults" : "");
  }
  stop.wait(o.duration_s);
  emulator.stop();
  const auto c = emulator.counters();
  CommandResult result;
  result.json = {{"device", emulator.device_path()},
                 {"scenario", settings.scenario.name},
                 {"twin_time_s", emulator.twin_time_s()},
                 {"scans_sent", c.scans_sent},
                 {"scans_skipped", c.scans_skipped},
                 {"telegrams_sent", c.telegrams_sent},
                 {"requests", c.requests},
                 {"naks_sent", c.naks_sent},
                 {"faults_injected", c.injected.total()}};
  for (const auto& [kind, count] : c.injected.by_kind()) {
    result.json["faults_by_kind"][kind] = count;
  }
  char text[512];
  std::snprintf(text, sizeof text,
                "served %llu requests and %llu scans (%llu skipped at the line rate) over %.1f s "
                "of twin time; %llu faults injected\n",
                static_cast<unsigned long long>(c.requests),
                static_cast<unsigned long long>(c.scans_sent),
                static_cast<unsigned long long>(c.scans_skipped), emulator.twin_time_s(),
                static_cast<unsigned long long>(c.injected.total()));
  result.text = text;
  return result;
}

}  // namespace

void register_emulate(CLI::App& app, const CommonOptions& common, CommandRunner& run) {
  auto* cmd = app.add_subcommand(
      "emulate",
      "Serve an emulated LMS 200 on a pseudo-terminal, driven by a twin scenario; prints the "
      "device path, serves until SIGINT/SIGTERM");
  auto o = std::make_shared<EmulateOptions>();
  cmd->add_option("scenario", o->scenario, "Scenario YAML file")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--recording", o->recording,
                  "Play this tofcompd recording instead of the twin (the scenario still gives "
                  "the device); the host must ask for the recorded variant")
      ->check(CLI::ExistingFile);
  cmd->add_option("--link", o->link,
                  "Also publish the device at this path (a symlink, kept across hang-ups)")
      ->type_name("PATH");
  cmd->add_option("--time-scale", o->time_scale,
                  "Twin seconds per wall second (1: real time; 0: as fast as the host reads)")
      ->check(at_least(0));
  cmd->add_option("--faults", o->fault_rate,
                  "Faults per telegram, split evenly over garbage, dropped bytes, corrupted "
                  "CRCs, stalls, hang-ups and resets (0.01: one in a hundred)")
      ->check(between(0, 1));
  cmd->add_option("--fault-seed", o->fault_seed, "Seed of the fault draws");
  cmd->add_option("--duration", o->duration_s, "Stop after this many wall seconds (0: never)")
      ->check(at_least(0));
  cmd->add_flag("--rs232", o->rs232, "An RS-232 unit: refuses 500 kBd");
  cmd->callback([&common, &run, o] { run = [&common, o] { return emulate(*o, common); }; });
}

}  // namespace tofcomp::cli
