// tofcomp's side of the peers' comparison (bench/peers/run.sh): the exact EM of §5
// (core/em_train.hpp) on a case written by bench/peers/make_data.py, from the same start as the
// numpy and flexmix peers. Prints one JSON line: the CPU time per plain EM iteration (a fixed
// run, best of REPEATS), and the converged fit by plain EM and by SQUAREM (iterations, E-steps,
// log-likelihood, CPU time). CPU time of this process, so that other load on the machine does
// not count.
//
// Usage: peer_engine DIR CASE ITERATIONS REPEATS [LABEL]
//   LABEL names the build in the output (default: tofcomp).
#include <time.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <limits>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/em_train.hpp"

namespace {

using tofcomp::core::EmAcceleration;
using tofcomp::core::EmStartingPoint;
using tofcomp::core::EmTrainOptions;
using tofcomp::core::EmTrainResult;

double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

std::vector<double> read_doubles(const std::string& path, std::size_t count) {
  std::ifstream in(path, std::ios::binary);
  std::vector<double> out(count);
  in.read(reinterpret_cast<char*>(out.data()), static_cast<std::streamsize>(count * sizeof(double)));
  if (!in) throw std::runtime_error("cannot read " + std::to_string(count) + " values from " + path);
  return out;
}

// The numbers of one "key": [a, b, ...] or "key": n of the case's JSON (written by make_data.py).
std::vector<double> json_numbers(const std::string& text, const std::string& key) {
  const std::regex pattern("\"" + key + "\": (\\[[^\\]]*\\]|[-0-9.e+]+)");
  std::smatch match;
  if (!std::regex_search(text, match, pattern)) throw std::runtime_error("no key " + key);
  std::string list = match[1].str();
  std::replace(list.begin(), list.end(), '[', ' ');
  std::replace(list.begin(), list.end(), ']', ' ');
  std::replace(list.begin(), list.end(), ',', ' ');
  std::istringstream in(list);
  std::vector<double> out;
  for (double v; in >> v;) out.push_back(v);
  return out;
}

Eigen::VectorXd vec(const std::vector<double>& v) {
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

struct Timed {
  EmTrainResult fit;
  double seconds = 0.0;
};

Timed run(const Eigen::MatrixXd& h, const Eigen::VectorXd& y, const EmTrainOptions& options) {
  const double t0 = cpu_seconds();
  Timed out{tofcomp::core::train_em(h, y, options), 0.0};
  out.seconds = cpu_seconds() - t0;
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5 && argc != 6) {
    std::fprintf(stderr, "usage: peer_engine DIR CASE ITERATIONS REPEATS [LABEL]\n");
    return 2;
  }
  const std::string dir = argv[1], name = argv[2];
  const int iterations = std::stoi(argv[3]), repeats = std::stoi(argv[4]);
  const std::string label = argc == 6 ? argv[5] : "tofcomp";
  std::ifstream meta_file(dir + "/" + name + ".json");
  const std::string meta((std::istreambuf_iterator<char>(meta_file)), {});
  const auto k = static_cast<Eigen::Index>(json_numbers(meta, "K")[0]);
  const auto p = static_cast<Eigen::Index>(json_numbers(meta, "p")[0]);
  const int m = static_cast<int>(json_numbers(meta, "M")[0]);
  const std::vector<double> h_values = read_doubles(dir + "/" + name + ".h.f64", static_cast<std::size_t>(k * p));
  const Eigen::MatrixXd h = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      h_values.data(), k, p);
  const Eigen::VectorXd y = vec(read_doubles(dir + "/" + name + ".y.f64", static_cast<std::size_t>(k)));
  EmStartingPoint start;
  start.theta = vec(json_numbers(meta, "theta"));
  start.mixture.mean = vec(json_numbers(meta, "mean"));
  start.mixture.variance = vec(json_numbers(meta, "variance"));
  start.mixture.weight = vec(json_numbers(meta, "weight"));

  EmTrainOptions options;
  options.modes = m;
  options.start = start;
  options.record_trace = false;
  // The peers' stopping rule is tofcomp's default; the iteration cap is lifted for plain EM.
  options.max_iterations = 100000;

  EmTrainOptions fixed = options;
  fixed.acceleration = EmAcceleration::None;
  fixed.max_iterations = iterations;
  fixed.weight_tolerance = 1e-300;
  fixed.log_likelihood_tolerance = 0.0;
  double best = std::numeric_limits<double>::infinity();
  for (int r = 0; r < repeats; ++r) best = std::min(best, run(h, y, fixed).seconds);

  EmTrainOptions plain_options = options;
  plain_options.acceleration = EmAcceleration::None;
  const Timed plain = run(h, y, plain_options);
  const Timed fast = run(h, y, options);
  std::printf(
      "{\"peer\": \"%s\", \"case\": \"%s\", \"s_per_iteration\": %.6g, "
      "\"iterations\": %d, \"log_likelihood\": %.10f, \"converged\": %s, \"fit_s\": %.6g, "
      "\"squarem_iterations\": %d, \"squarem_e_steps\": %d, \"squarem_log_likelihood\": %.10f, "
      "\"squarem_converged\": %s, \"squarem_fit_s\": %.6g}\n",
      label.c_str(), name.c_str(), best / iterations, plain.fit.iterations, plain.fit.log_likelihood,
      plain.fit.converged ? "true" : "false", plain.seconds, fast.fit.iterations,
      fast.fit.likelihood_evaluations, fast.fit.log_likelihood,
      fast.fit.converged ? "true" : "false", fast.seconds);
  return 0;
}
