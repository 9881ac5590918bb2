#include "core/cramer_rao.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "core/error.hpp"
#include "core/validation.hpp"

namespace tofcomp::core {

namespace {

// The phases at which I is evaluated and averaged (midpoints of equal steps).
constexpr int kRoundingPhases = 16;
// Steps beyond this many standard deviations of every mode hold no probability worth counting.
constexpr double kTailSigmas = 10.0;
// A step whose probability is below this adds nothing to I (and would divide by ~0).
constexpr double kNegligibleProbability = 1e-300;

// P(a < Z < b) for a standard normal Z, from the nearer tail so that a step far in one tail is
// not the difference of two numbers near 1.
double normal_interval(double a, double b) {
  const auto upper_tail = [](double z) { return 0.5 * std::erfc(z / std::numbers::sqrt2); };
  if (a >= 0.0) return upper_tail(a) - upper_tail(b);
  if (b <= 0.0) return upper_tail(-b) - upper_tail(-a);
  return 1.0 - upper_tail(b) - upper_tail(-a);
}

double normal_pdf(double z) {
  return std::exp(-0.5 * z * z) / std::sqrt(2.0 * std::numbers::pi);
}

}  // namespace

double range_fisher_information(const MixtureParameters& modes, double resolution_mm) {
  modes.validate();
  require_positive(resolution_mm, "resolution_mm");
  const Eigen::ArrayXd sigma = modes.variance.array().sqrt();
  const double low = ((modes.mean.array() - kTailSigmas * sigma).minCoeff()) / resolution_mm;
  const double high = ((modes.mean.array() + kTailSigmas * sigma).maxCoeff()) / resolution_mm;
  const auto first = static_cast<long>(std::floor(low)) - 1;
  const auto last = static_cast<long>(std::ceil(high)) + 1;
  double total = 0.0;
  for (int phase = 0; phase < kRoundingPhases; ++phase) {
    const double c = resolution_mm * (phase + 0.5) / kRoundingPhases;
    double information = 0.0;
    for (long k = first; k <= last; ++k) {
      const double lower = (static_cast<double>(k) - 0.5) * resolution_mm - c;
      const double upper = (static_cast<double>(k) + 0.5) * resolution_mm - c;
      double p = 0.0;
      double dp = 0.0;
      for (int i = 0; i < modes.modes(); ++i) {
        const double a = (lower - modes.mean[i]) / sigma[i];
        const double b = (upper - modes.mean[i]) / sigma[i];
        p += modes.weight[i] * normal_interval(a, b);
        dp += modes.weight[i] * (normal_pdf(a) - normal_pdf(b)) / sigma[i];
      }
      if (p > kNegligibleProbability) information += dp * dp / p;
    }
    total += information;
  }
  return total / kRoundingPhases;
}

double cramer_rao_mae_mm(double range_information, Eigen::Index n) {
  if (n < 1) {
    throw InvalidInput("a window needs at least one range (n = " + std::to_string(n) + ")");
  }
  require_positive(range_information, "Fisher information of a range");
  return std::sqrt(2.0 / std::numbers::pi) *
         std::sqrt(1.0 / (static_cast<double>(n) * range_information));
}

}  // namespace tofcomp::core
