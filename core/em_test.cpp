#include "core/em_test.hpp"

#include <cmath>

#include "core/error.hpp"
#include "core/validation.hpp"

namespace tofcomp::core {
namespace {

// M-step of Eq. 23 (either form) given the responsibilities.
double distance_m_step(MStep kind, const Eigen::VectorXd& corrected, const Eigen::MatrixXd& r,
                       const MixtureParameters& m) {
  if (kind == MStep::PaperAsPrinted) {
    const Eigen::VectorXd c_inverse = (r * m.variance).cwiseInverse();
    return c_inverse.dot(corrected) / c_inverse.sum();
  }
  const Eigen::MatrixXd w = r * m.variance.cwiseInverse().asDiagonal();
  const Eigen::VectorXd total = w.rowwise().sum();
  return (total.dot(corrected) - w.colwise().sum().dot(m.mean)) / total.sum();
}

}  // namespace

double distance_standard_deviation(const Eigen::Ref<const Eigen::VectorXd>& corrected, double d,
                                   const Eigen::MatrixXd& r, const Eigen::VectorXd& mean,
                                   const Eigen::MatrixXd& precision,
                                   const Eigen::Ref<const Eigen::MatrixXd>& mode_shift) {
  const bool shifted = mode_shift.size() > 0;
  double observed = 0.0;
  double complete = 0.0;
  for (Eigen::Index k = 0; k < corrected.size(); ++k) {
    double info = 0.0;
    double second = 0.0;
    double score = 0.0;
    for (Eigen::Index i = 0; i < mean.size(); ++i) {
      const double e = corrected[k] - d - mean[i] - (shifted ? mode_shift(k, i) : 0.0);
      const double p = precision(k, i);
      info += r(k, i) * p;
      second += r(k, i) * e * e * p * p;
      score += r(k, i) * e * p;
    }
    complete += info;
    observed += info - second + score * score;
  }
  return 1.0 / std::sqrt(observed > 0.0 ? observed : complete);
}

void validate_test_arguments(const Eigen::Ref<const Eigen::VectorXd>& y,
                             const Eigen::Ref<const Eigen::VectorXd>& bias,
                             const EmTestOptions& options, std::optional<double> initial_distance) {
  if (y.size() == 0) throw InvalidInput("EM testing needs at least one range");
  require_same_length(y.size(), "y", bias.size(), "H theta");
  require_finite(y, "y");
  require_finite(bias, "H theta");
  if (options.max_iterations < 1) throw InvalidInput("EM testing needs max_iterations >= 1");
  if (!(options.distance_tolerance > 0.0)) {
    throw InvalidInput("distance_tolerance must be positive");
  }
  if (initial_distance) require_finite(*initial_distance, "initial distance");
}

EmTestResult test_em(const Eigen::Ref<const Eigen::VectorXd>& y,
                     const Eigen::Ref<const Eigen::VectorXd>& bias,
                     const MixtureParameters& mixture, const EmTestOptions& options,
                     std::optional<double> initial_distance) {
  validate_test_arguments(y, bias, options, initial_distance);
  mixture.validate();

  const Eigen::VectorXd corrected = y - bias;
  EmTestResult result;
  double d = initial_distance                          ? *initial_distance
             : options.m_step == MStep::PaperAsPrinted ? y.mean()
                                                       : corrected.mean() - mixture.mean_offset();
  d = iterate_distance(
      d, options, result,
      [&](double at) {  // E-step, Eq. 22
        return mixture_e_step(corrected.array() - at, mixture, result.responsibilities);
      },
      [&] {  // M-step, Eq. 23
        return distance_m_step(options.m_step, corrected, result.responsibilities, mixture);
      });
  result.distance = d;
  const Eigen::MatrixXd precision =
      Eigen::VectorXd::Ones(y.size()) * mixture.variance.cwiseInverse().transpose();
  result.distance_std =
      distance_standard_deviation(corrected, d, result.responsibilities, mixture.mean, precision);
  return result;
}

}  // namespace tofcomp::core
