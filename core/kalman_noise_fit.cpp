#include "core/kalman_noise_fit.hpp"

#include <cmath>

#include "core/error.hpp"

namespace tofcomp::core {
namespace {

constexpr int kMinimumReadings = 3;
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

  // Golden-section search of one level's log10 over its bracket; sets the level in `noise`.
  void maximize_level(ThermalNoise& noise, int level) {
    const auto i = static_cast<std::size_t>(level);
    double lo = options_.min_log10[i];
    double hi = options_.max_log10[i];
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
      prior_at_case_temperature(parameters, log.case_c[0], log.power_on_fraction[0],
                                options.prior_case_std_c, options.prior_junction_std_c);
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
  // Fit the levels not held; judge each by its profile; hold the undetermined and fit again.
  for (int round = 0; round < kKalmanNoiseLevelCount; ++round) {
    noise = start;
    for (int sweep = 0; sweep < options.sweeps; ++sweep) {
      for (int level = 0; level < kKalmanNoiseLevelCount; ++level) {
        if (!held[static_cast<std::size_t>(level)]) search.maximize_level(noise, level);
      }
    }
    const double best = search.evaluate(noise);
    bool newly_held = false;
    for (int level = 0; level < kKalmanNoiseLevelCount; ++level) {
      const auto i = static_cast<std::size_t>(level);
      KalmanNoiseLevelFit& judged = fit.levels[i];
      const double value = level_of(noise, level);
      const double step = std::log10(options.profile_factor);
      judged.value = value;
      judged.profile_drop_down = best - search.at(noise, level, std::log10(value) - step);
      judged.profile_drop_up = best - search.at(noise, level, std::log10(value) + step);
      judged.held = held[i];
      if (!held[i] && judged.profile_drop_down < options.determined_drop &&
          judged.profile_drop_up < options.determined_drop) {
        held[i] = true;
        judged.held = true;
        judged.value = level_of(fit.start, level);
        newly_held = true;
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
