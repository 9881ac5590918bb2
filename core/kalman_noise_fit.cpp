#include "core/kalman_noise_fit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.hpp"

namespace tofcomp::core {
namespace {

constexpr int kMinimumReadings = 3;
// Rounds of sweeps, probes and holds before the search stops where it is.
constexpr int kMaxRounds = 8;
// A probe must gain this much log-likelihood to move the search.
constexpr double kImprovement = 0.01;
// After the first round a level is searched this many decades either side of where it is.
constexpr double kLocalSearchDecades = 1.5;
// 1 / golden ratio: the share of a bracket each golden-section step keeps.
const double kGoldenShare = (std::sqrt(5.0) - 1.0) / 2.0;

double& level_of(ThermalNoise& noise, int level) {
  switch (static_cast<KalmanNoiseLevel>(level)) {
    case KalmanNoiseLevel::kCaseProcess:
      return noise.case_process_psd_k2_per_s;
    case KalmanNoiseLevel::kJunctionProcess:
      return noise.junction_process_psd_k2_per_s;
    case KalmanNoiseLevel::kSensor:
      break;
  }
  return noise.measurement_variance_k2;
}

double level_of(const ThermalNoise& noise, int level) {
  ThermalNoise copy = noise;
  return level_of(copy, level);
}

class NoiseSearch {
 public:
  NoiseSearch(const CaseTemperatureLog& log, const ThermalParameters& parameters,
              const NoiseFitOptions& options)
      : log_(log), parameters_(parameters), options_(options) {}

  double evaluate(const ThermalNoise& noise) {
    ++evaluations_;
    return innovations_log_likelihood(log_, parameters_, noise, options_);
  }

  // The log-likelihood with one level set to 10^x, the others as in `noise`.
  double at(ThermalNoise noise, int level, double log10_value) {
    level_of(noise, level) = std::pow(10.0, log10_value);
    return evaluate(noise);
  }

  // Golden-section search of one level's log10 over its bracket, or over `half_width` decades
  // about its current value when that is finite; sets the level in `noise`.
  void maximize_level(ThermalNoise& noise, int level, double half_width) {
    const auto i = static_cast<std::size_t>(level);
    const double now = std::log10(level_of(noise, level));
    double lo = std::max(options_.min_log10[i], now - half_width);
    double hi = std::min(options_.max_log10[i], now + half_width);
    double x1 = hi - kGoldenShare * (hi - lo);
    double x2 = lo + kGoldenShare * (hi - lo);
    double f1 = at(noise, level, x1);
    double f2 = at(noise, level, x2);
    while (hi - lo > options_.log10_tolerance) {
      if (f1 >= f2) {
        hi = x2;
        x2 = x1;
        f2 = f1;
        x1 = hi - kGoldenShare * (hi - lo);
        f1 = at(noise, level, x1);
      } else {
        lo = x1;
        x1 = x2;
        f1 = f2;
        x2 = lo + kGoldenShare * (hi - lo);
        f2 = at(noise, level, x2);
      }
    }
    level_of(noise, level) = std::pow(10.0, f1 >= f2 ? x1 : x2);
  }

  int evaluations() const { return evaluations_; }

 private:
  const CaseTemperatureLog& log_;
  const ThermalParameters& parameters_;
  const NoiseFitOptions& options_;
  int evaluations_ = 0;
};

}  // namespace

const char* kalman_noise_level_name(KalmanNoiseLevel level) {
  switch (level) {
    case KalmanNoiseLevel::kCaseProcess:
      return "case process noise q_c";
    case KalmanNoiseLevel::kJunctionProcess:
      return "junction process noise q_j";
    case KalmanNoiseLevel::kSensor:
      break;
  }
  return "sensor noise r";
}

const char* kalman_noise_level_key(KalmanNoiseLevel level) {
  switch (level) {
    case KalmanNoiseLevel::kCaseProcess:
      return "case_process";
    case KalmanNoiseLevel::kJunctionProcess:
      return "junction_process";
    case KalmanNoiseLevel::kSensor:
      break;
  }
  return "sensor";
}

double innovations_log_likelihood(const CaseTemperatureLog& log,
                                  const ThermalParameters& parameters, const ThermalNoise& noise,
                                  const NoiseFitOptions& options) {
  const ThermalBelief prior =
      prior_at_case_temperature(parameters, log.case_c[0], log.ambient_c[0],
                                options.prior_case_std_c);
  ThermalKalmanFilter filter(parameters, noise, prior);
  filter.update(log.case_c[0]);
  for (Eigen::Index k = 1; k < log.times_s.size(); ++k) {
    // The on fraction and ambient of reading k − 1 hold until reading k (CaseTemperatureLog).
    filter.predict(log.times_s[k] - log.times_s[k - 1], log.power_on_fraction[k - 1],
                   log.ambient_c[k - 1]);
    filter.update(log.case_c[k]);
  }
  return filter.log_likelihood();
}

KalmanNoiseFit fit_kalman_noise(const CaseTemperatureLog& log, const ThermalParameters& parameters,
                                const ThermalNoise& start, const NoiseFitOptions& options) {
  log.validate();
  start.validate();
  if (log.times_s.size() < kMinimumReadings) {
    throw InvalidInput("the Kalman noise levels need at least " +
                       std::to_string(kMinimumReadings) + " case readings");
  }
  NoiseSearch search(log, parameters, options);
  KalmanNoiseFit fit;
  fit.start = start;
  fit.start_log_likelihood = search.evaluate(start);

  std::array<bool, kKalmanNoiseLevelCount> held{};
  ThermalNoise noise = start;
  const double step = std::log10(options.profile_factor);
  // Fit the levels not held; probe each a factor up and down. A probe that is better moves the
  // search there (the golden sections assume one maximum per level, which a noise level's
  // profile need not have) and the sweeps go on; otherwise a level whose start value the log
  // does not reject is held there, and the others are fitted again with it held.
  for (int round = 0; round < kMaxRounds; ++round) {
    for (int sweep = 0; sweep < options.sweeps; ++sweep) {
      for (int level = 0; level < kKalmanNoiseLevelCount; ++level) {
        if (!held[static_cast<std::size_t>(level)]) {
          // The first round searches each whole bracket; later ones near where the last ended.
          search.maximize_level(noise, level,
                                round == 0 ? std::numeric_limits<double>::infinity()
                                           : kLocalSearchDecades);
        }
      }
    }
    const double best = search.evaluate(noise);
    bool moved = false;
    for (int level = 0; level < kKalmanNoiseLevelCount; ++level) {
      const auto i = static_cast<std::size_t>(level);
      KalmanNoiseLevelFit& judged = fit.levels[i];
      const double value = std::log10(level_of(noise, level));
      const double down = std::max(value - step, options.min_log10[i]);
      const double up = std::min(value + step, options.max_log10[i]);
      judged.value = level_of(noise, level);
      judged.held = held[i];
      judged.profile_drop_down = best - search.at(noise, level, down);
      judged.profile_drop_up = best - search.at(noise, level, up);
      judged.start_drop = best - search.at(noise, level, std::log10(level_of(start, level)));
      if (held[i] || moved) continue;
      if (std::min(judged.profile_drop_down, judged.profile_drop_up) < -kImprovement) {
        level_of(noise, level) = std::pow(
            10.0, judged.profile_drop_down < judged.profile_drop_up ? down : up);
        moved = true;
      }
    }
    if (moved) continue;
    // A level whose start the log does not reject (a likelihood-ratio test at 5 %) stays there.
    bool newly_held = false;
    for (int level = 0; level < kKalmanNoiseLevelCount; ++level) {
      const auto i = static_cast<std::size_t>(level);
      KalmanNoiseLevelFit& judged = fit.levels[i];
      if (!held[i] && judged.start_drop < options.determined_drop) {
        held[i] = true;
        judged.held = true;
        judged.value = level_of(start, level);
        level_of(noise, level) = level_of(start, level);
        newly_held = true;
        break;  // one at a time: the others are fitted again with it held
      }
    }
    if (!newly_held) break;
  }
  for (int level = 0; level < kKalmanNoiseLevelCount; ++level) {
    if (held[static_cast<std::size_t>(level)]) level_of(noise, level) = level_of(start, level);
  }
  fit.noise = noise;
  fit.log_likelihood = search.evaluate(noise);
  fit.evaluations = search.evaluations();
  return fit;
}

}  // namespace tofcomp::core
