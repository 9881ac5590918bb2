// Crash safety of calibration writes: a child process rewrites a calibration file in a loop,
// alternating two distinguishable calibrations, and is killed with SIGKILL at a random moment
// (0–20 ms, seeded, different each round). The file must then load with the real reader as one
// of the two, every value bit for bit. A control writes the same text with a plain
// std::ofstream under the same kill and shows the file does tear then, so the check can fail.
//
// What the atomic writer (io/atomic_file.hpp) leaves behind: a kill gives its destructor no
// chance to run, so the temporary file it was filling stays, as a hidden
// ".calibration.yaml.XXXXXX" beside the target; at most one per kill, never under the target's
// name, and later writes neither remove nor reuse it (mkstemp picks a fresh name).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <random>
#include <regex>
#include <set>
#include <string>
#include <thread>

#include "io/calibration_file.hpp"
#include "tests/support/temporary_directory.hpp"

namespace tofcomp::io {
namespace {

namespace fs = std::filesystem;

// Large enough that one write takes a while (a 1016-term basis, 200 kB of notes), with values
// drawn at full double precision from a seed, so that the two calibrations differ everywhere.
core::Calibration make_calibration(char tag, unsigned seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  core::Calibration c;
  c.thermal = {0.18 + 0.01 * uniform(random), 0.5, 60.0, 2000.0, 10.0};
  c.ambient_c = 21.0 + uniform(random);
  c.model.basis = core::Basis(
      {core::BasisTerm{core::BasisKind::Polynomial, 16, core::PolynomialForm::Legendre, 0.0},
       core::BasisTerm{core::BasisKind::Fourier, 500, core::PolynomialForm::Legendre, 0.1}},
      core::TemperatureScaling{26.8, 2.0});
  c.model.theta.resize(c.model.basis.columns());
  for (Eigen::Index i = 0; i < c.model.theta.size(); ++i) c.model.theta[i] = uniform(random);
  c.model.mixture.mean = Eigen::Vector2d(-2.0 + uniform(random), 2.5 + uniform(random));
  c.model.mixture.variance = Eigen::Vector2d(0.81, 1.21);
  c.model.mixture.weight = Eigen::Vector2d(0.55, 0.45);
  std::string notes;
  while (notes.size() < 200'000) {
    notes += std::string("calibration ") + tag + " line " + std::to_string(notes.size()) + "; ";
  }
  c.provenance = {std::string("data-") + tag + ".csv", "2026-11-23T00:00:00Z", "tofcomp 0.1.0",
                  20000, notes};
  return c;
}

bool identical(const core::Calibration& x, const core::Calibration& y) {
  return x.thermal.r1_k_per_w == y.thermal.r1_k_per_w &&
         x.thermal.r2_k_per_w == y.thermal.r2_k_per_w &&
         x.thermal.c1_j_per_k == y.thermal.c1_j_per_k &&
         x.thermal.c2_j_per_k == y.thermal.c2_j_per_k && x.thermal.power_w == y.thermal.power_w &&
         x.kalman_noise.case_process_psd_k2_per_s == y.kalman_noise.case_process_psd_k2_per_s &&
         x.kalman_noise.junction_process_psd_k2_per_s ==
             y.kalman_noise.junction_process_psd_k2_per_s &&
         x.kalman_noise.measurement_variance_k2 == y.kalman_noise.measurement_variance_k2 &&
         x.ambient_c == y.ambient_c && x.model.basis.describe() == y.model.basis.describe() &&
         x.model.theta.size() == y.model.theta.size() && x.model.theta == y.model.theta &&
         x.model.mixture.mean == y.model.mixture.mean &&
         x.model.mixture.variance == y.model.mixture.variance &&
         x.model.mixture.weight == y.model.mixture.weight &&
         x.provenance.data_set == y.provenance.data_set &&
         x.provenance.created_utc == y.provenance.created_utc &&
         x.provenance.software_version == y.provenance.software_version &&
         x.provenance.samples == y.provenance.samples && x.provenance.notes == y.provenance.notes;
}

enum class Found { First, Second, Neither };

// What the real reader makes of the file: one of the two calibrations, or neither (an error, or
// values that match neither).
Found load_and_identify(const fs::path& file, const core::Calibration& first,
                        const core::Calibration& second, std::string& error) {
  try {
    const core::Calibration loaded = read_calibration_file(file.string());
    if (identical(loaded, first)) return Found::First;
    if (identical(loaded, second)) return Found::Second;
    error = "loaded, but matches neither calibration";
  } catch (const std::exception& e) {
    error = e.what();
  }
  return Found::Neither;
}

// Runs `write(i)` for i = 0, 1, 2, ... in a child process, waits until the first write has
// completed (the child says so through a pipe), lets it go on for `delay`, then SIGKILLs it.
// Returns false, with a failure recorded, when the child did not get that far or died otherwise.
bool kill_while_writing(const std::function<void(int)>& write, std::chrono::microseconds delay) {
  int pipe_fds[2];
  if (::pipe2(pipe_fds, O_CLOEXEC) != 0) {
    ADD_FAILURE() << "pipe: " << std::strerror(errno);
    return false;
  }
  const pid_t child = ::fork();
  if (child < 0) {
    ADD_FAILURE() << "fork: " << std::strerror(errno);
    return false;
  }
  if (child == 0) {
    ::close(pipe_fds[0]);
    try {
      for (int i = 0;; ++i) {
        write(i);
        if (i == 0) {
          const char started = 1;
          if (::write(pipe_fds[1], &started, 1) != 1) ::_exit(2);
          ::close(pipe_fds[1]);
        }
      }
    } catch (...) {
      ::_exit(1);
    }
  }
  ::close(pipe_fds[1]);
  pollfd started{pipe_fds[0], POLLIN, 0};
  const bool first_write_done = ::poll(&started, 1, 60'000) == 1;
  ::close(pipe_fds[0]);
  if (first_write_done) std::this_thread::sleep_for(delay);
  ::kill(child, SIGKILL);
  int status = 0;
  ::waitpid(child, &status, 0);
  if (!first_write_done || !WIFSIGNALED(status) || WTERMSIG(status) != SIGKILL) {
    ADD_FAILURE() << "the writing child did not run until killed (first write done: "
                  << first_write_done << ", wait status " << status << ")";
    return false;
  }
  return true;
}

// Everything in `directory` but `target`.
std::set<std::string> others_in(const fs::path& directory, const std::string& target) {
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(directory)) {
    const std::string name = entry.path().filename().string();
    if (name != target) names.insert(name);
  }
  return names;
}

TEST(CalibrationCrash, KillDuringAtomicWriteLeavesOneOfTheCompleteCalibrations) {
  constexpr int kRounds = 60;
  const core::Calibration first = make_calibration('A', 1);
  const core::Calibration second = make_calibration('B', 2);
  ASSERT_FALSE(identical(first, second));
  const test::TemporaryDirectory directory{"calibration-crash"};
  const std::string target = "calibration.yaml";
  const fs::path file = directory.path() / target;
  // The only names the writer's temporary files take: mkstemp's six characters after the
  // hidden target name.
  const std::regex temporary_name(R"(\.calibration\.yaml\.[A-Za-z0-9]{6})");

  std::mt19937 random(20151123);
  std::uniform_int_distribution<int> delay_us(0, 20'000);
  int found_first = 0;
  int found_second = 0;
  std::set<std::string> leftovers;
  for (int round = 0; round < kRounds; ++round) {
    const auto delay = std::chrono::microseconds(delay_us(random));
    ASSERT_TRUE(kill_while_writing(
        [&](int i) { write_calibration_file(file.string(), i % 2 == 0 ? first : second); }, delay))
        << "round " << round;

    std::string error;
    const Found found = load_and_identify(file, first, second, error);
    ASSERT_NE(found, Found::Neither)
        << "round " << round << ", killed after " << delay.count() << " us: " << error;
    (found == Found::First ? found_first : found_second) += 1;

    const std::set<std::string> now = others_in(directory.path(), target);
    for (const std::string& name : now) {
      EXPECT_TRUE(std::regex_match(name, temporary_name)) << "round " << round << ": " << name;
    }
    EXPECT_LE(now.size(), leftovers.size() + 1) << "round " << round << ": more than one new file";
    for (const std::string& name : leftovers) EXPECT_EQ(now.count(name), 1u) << name;
    leftovers = now;
  }
  std::cout << "atomic writes killed " << kRounds << " times: " << found_first << " left A, "
            << found_second << " left B, " << leftovers.size() << " temporary files left behind\n";

  // A write that completes adds no file and is read back whole.
  write_calibration_file(file.string(), second);
  EXPECT_EQ(others_in(directory.path(), target), leftovers);
  std::string error;
  EXPECT_EQ(load_and_identify(file, first, second, error), Found::Second) << error;
}

TEST(CalibrationCrash, KillDuringPlainWriteTearsTheFile) {
  constexpr int kRounds = 20;
  const core::Calibration first = make_calibration('A', 1);
  const core::Calibration second = make_calibration('B', 2);
  const std::string first_text = calibration_to_yaml(first);
  const std::string second_text = calibration_to_yaml(second);
  const test::TemporaryDirectory directory{"calibration-crash"};
  const fs::path file = directory.path() / "calibration.yaml";

  std::mt19937 random(20151124);
  std::uniform_int_distribution<int> delay_us(0, 20'000);
  int torn = 0;
  std::string example;
  for (int round = 0; round < kRounds; ++round) {
    ASSERT_TRUE(kill_while_writing(
        [&](int i) {
          std::ofstream out(file, std::ios::trunc);
          out << (i % 2 == 0 ? first_text : second_text);
        },
        std::chrono::microseconds(delay_us(random))));
    std::string error;
    if (load_and_identify(file, first, second, error) == Found::Neither) {
      ++torn;
      example = error;
    }
  }
  std::cout << "plain writes killed " << kRounds << " times: " << torn
            << " left a torn file, e.g.: " << example.substr(0, 200) << "\n";
  // The file is whole only between one write's close and the next one's truncation, so nearly
  // every kill finds it torn.
  EXPECT_GE(torn, kRounds / 2);
}

}  // namespace
}  // namespace tofcomp::io
