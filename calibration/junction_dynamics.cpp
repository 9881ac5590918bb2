#include "calibration/junction_dynamics.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <Eigen/QR>
#include <optional>
#include <tuple>
#include <utility>

#include "calibration/final_fit.hpp"
#include "calibration/junction_estimate.hpp"
#include "core/error.hpp"
#include "core/gaussian_mixture.hpp"
#include "core/sign_flip_max_t.hpp"

namespace tofcomp::calibration {
namespace {

// The search box: this many prior standard deviations of each product's logarithm on either
// side of the datasheet's value (with the prior's ln 2 per parameter, a factor of about 7).
constexpr double kSearchPriorSigmas = 2.0;
// The first simplex and one step of Nelder-Mead.
constexpr int kMinEvaluations = 4;

constexpr double kMinusInfinity = -std::numeric_limits<double>::infinity();

struct LogDynamics {
  double log_rise = 0.0;
  double log_time_constant = 0.0;
};

LogDynamics log_of(const JunctionDynamics& d) {
  return {std::log(d.rise_k), std::log(d.time_constant_s)};
}
JunctionDynamics dynamics_at(const LogDynamics& x) {
  return {std::exp(x.log_rise), std::exp(x.log_time_constant)};
}

// Σ over each block of kJunctionBlockRanges consecutive entries (the last block may be shorter).
Eigen::VectorXd block_sums(const Eigen::VectorXd& values) {
  const Eigen::Index blocks = (values.size() + kJunctionBlockRanges - 1) / kJunctionBlockRanges;
  Eigen::VectorXd sums(blocks);
  for (Eigen::Index b = 0; b < blocks; ++b) {
    const Eigen::Index begin = b * kJunctionBlockRanges;
    sums[b] = values.segment(begin, std::min(kJunctionBlockRanges, values.size() - begin)).sum();
  }
  return sums;
}

// The one-sided t-test that `point`'s ranges gain over `reference`'s, over the same blocks:
// (t, p); (0, 1) when `point` has no fit.
std::pair<double, double> block_gain_test(const JunctionDynamicsPoint& point,
                                          const JunctionDynamicsPoint& reference) {
  if (point.block_log_likelihood.size() != reference.block_log_likelihood.size()) return {0.0, 1.0};
  const core::BlockGainTest test =
      core::block_gain_t_test(point.block_log_likelihood - reference.block_log_likelihood);
  return {test.t, test.p};
}

// Evaluates points of the search, each EM fit warm-started from the last successful one.
class Evaluator {
 public:
  Evaluator(const JunctionDynamicsProblem& problem, const JunctionDynamicsOptions& options,
            const JunctionDynamicsProgress& progress)
      : problem_(problem),
        options_(options),
        progress_(progress),
        noise_(problem.kalman_noise),
        warm_(problem.start),
        grid_(thermal_record_grid(problem.data, problem.ambient_fallback_c)) {
    y_minus_d_ = problem.data.range_mm - problem.data.true_range_mm;
  }

  // The filter's levels of the points evaluated from now on.
  void use_noise(const core::ThermalNoise& noise) { noise_ = noise; }

  // The point at x; throws when `required` and its fit fails, else scores a failure −∞.
  JunctionDynamicsPoint evaluate(const LogDynamics& x, bool required, JunctionDynamicsFit& fit) {
    JunctionDynamicsPoint point;
    point.dynamics = dynamics_at(x);
    const core::ThermalParameters parameters =
        with_junction_dynamics(problem_.case_fit.parameters, point.dynamics);
    point.prior_cost = prior_cost(parameters);
    try {
      const SmoothedJunction junction = junction_at_ranges(grid_, parameters, noise_);
      const Eigen::MatrixXd h =
          basis_spanning(problem_.basis, junction.junction_c).design_matrix(junction.junction_c);
      core::EmTrainOptions em = options_.em;
      em.modes = problem_.modes;
      em.record_trace = false;
      // The mixture starts where the last fit ended; θ's coordinates follow the rescaled basis,
      // so θ starts at least squares.
      em.start = least_squares_start(h, y_minus_d_, warm_.mixture);
      // At some junctions the data show fewer modes than the structure search counted on the
      // case-log junction: a mode empties, and the likelihood there is that of the modes left
      // (the limit of its weight going to zero), not a failure. (Taken for a failure, such points
      // cornered the search: on a twin day record 7 of its 37 points, the last four among them.)
      const core::EmTrainResult result = train_em_dropping_emptied_modes(h, y_minus_d_, em).em;
      point.ranges_log_likelihood = result.log_likelihood;
      point.block_log_likelihood = block_sums(
          core::mixture_log_densities(y_minus_d_ - h * result.theta, result.mixture));
      // The next point starts from this one's fit when it kept every mode.
      if (result.mixture.modes() == problem_.modes) {
        warm_ = core::EmStartingPoint{result.theta, result.mixture};
      }
    } catch (const core::Error&) {
      if (required) throw;
      point.ranges_log_likelihood = kMinusInfinity;
    }
    fit.evaluated.push_back(point);
    if (progress_) progress_(point);
    return point;
  }

 private:
  // ½ Σ ((log p − log p₀) / s)² over the five parameters, p₀ the datasheet's.
  double prior_cost(const core::ThermalParameters& parameters) const {
    const auto values = core::thermal_parameter_values(parameters);
    const auto prior = core::thermal_parameter_values(problem_.case_fit.prior);
    const double s = problem_.case_fit_options.prior_log_std;
    double cost = 0.0;
    for (std::size_t i = 0; i < values.size(); ++i) {
      const double z = std::log(values[i] / prior[i]) / s;
      cost += 0.5 * z * z;
    }
    return cost;
  }

  const JunctionDynamicsProblem& problem_;
  const JunctionDynamicsOptions& options_;
  const JunctionDynamicsProgress& progress_;
  core::ThermalNoise noise_;
  core::EmStartingPoint warm_;
  // Every point smooths the same readings on the same grid.
  ThermalRecordGrid grid_;
  Eigen::VectorXd y_minus_d_;
};

// Nelder-Mead (reflection 1, expansion 2, contraction ½, shrink ½) from `start`, whose value is
// `start_value`, with a first simplex of options.initial_log_step along each coordinate (towards
// the inside of the box), until the simplex's values agree within options.value_tolerance or its
// extent is below options.log_tolerance, or options.max_evaluations are spent.
template <typename F>
void minimize_nelder_mead(const F& f, const Eigen::Vector2d& start, const JunctionDynamicsOptions& options,
                          double start_value, const Eigen::Vector2d& box_low,
                          const Eigen::Vector2d& box_high) {
  std::array<Eigen::Vector2d, 3> x{start, start, start};
  std::array<double, 3> value{start_value, 0.0, 0.0};
  int evaluations = 0;
  for (int i = 0; i < 2; ++i) {
    const double room_up = box_high[i] - start[i];
    x[static_cast<std::size_t>(i) + 1][i] +=
        room_up >= options.initial_log_step ? options.initial_log_step : -options.initial_log_step;
    value[static_cast<std::size_t>(i) + 1] = f(x[static_cast<std::size_t>(i) + 1]);
    ++evaluations;
  }
  const auto clamp = [&](const Eigen::Vector2d& v) { return v.cwiseMax(box_low).cwiseMin(box_high).eval(); };
  while (evaluations < options.max_evaluations) {
    std::array<int, 3> order{0, 1, 2};
    std::sort(order.begin(), order.end(), [&](int a, int b) {
      return value[static_cast<std::size_t>(a)] < value[static_cast<std::size_t>(b)];
    });
    const auto at = [&](int k) -> Eigen::Vector2d& { return x[static_cast<std::size_t>(order[static_cast<std::size_t>(k)])]; };
    const auto val = [&](int k) -> double& { return value[static_cast<std::size_t>(order[static_cast<std::size_t>(k)])]; };
    const double extent = std::max((at(1) - at(0)).cwiseAbs().maxCoeff(), (at(2) - at(0)).cwiseAbs().maxCoeff());
    if (val(2) - val(0) < options.value_tolerance || extent < options.log_tolerance) break;
    const Eigen::Vector2d centroid = 0.5 * (at(0) + at(1));
    const Eigen::Vector2d reflected = clamp(centroid + (centroid - at(2)));
    const double reflected_value = f(reflected);
    ++evaluations;
    if (reflected_value < val(0)) {
      const Eigen::Vector2d expanded = clamp(centroid + 2.0 * (centroid - at(2)));
      const double expanded_value = f(expanded);
      ++evaluations;
      if (expanded_value < reflected_value) {
        at(2) = expanded;
        val(2) = expanded_value;
      } else {
        at(2) = reflected;
        val(2) = reflected_value;
      }
    } else if (reflected_value < val(1)) {
      at(2) = reflected;
      val(2) = reflected_value;
    } else {
      const Eigen::Vector2d contracted = centroid + 0.5 * (at(2) - centroid);
      const double contracted_value = f(contracted);
      ++evaluations;
      if (contracted_value < val(2)) {
        at(2) = contracted;
        val(2) = contracted_value;
      } else {
        for (int k = 1; k < 3; ++k) {
          at(k) = at(0) + 0.5 * (at(k) - at(0));
          val(k) = f(at(k));
          ++evaluations;
        }
      }
    }
  }
}

}  // namespace

JunctionDynamics junction_dynamics_of(const core::ThermalParameters& parameters) {
  return {parameters.power_w * parameters.r1_k_per_w,
          parameters.r1_k_per_w * parameters.c1_j_per_k};
}

core::ThermalParameters with_junction_dynamics(const core::ThermalParameters& parameters,
                                               const JunctionDynamics& dynamics) {
  core::ThermalParameters out = parameters;
  out.r1_k_per_w = dynamics.rise_k / parameters.power_w;
  out.c1_j_per_k = dynamics.time_constant_s / out.r1_k_per_w;
  return out;
}

bool JunctionDynamicsFit::ranges_answer_above_start() const {
  return !replaced && refused_by_final_fit.empty() && best.log_posterior() > start.log_posterior();
}

void JunctionDynamicsFit::take_ranges_answer() {
  if (!ranges_answer_above_start()) return;
  replaced = true;
  replaced_untested = true;
}

core::EmStartingPoint least_squares_start(const Eigen::MatrixXd& h,
                                          const Eigen::VectorXd& y_minus_d,
                                          const core::MixtureParameters& mixture) {
  const double offset = mixture.weight.dot(mixture.mean);
  return {h.colPivHouseholderQr().solve((y_minus_d.array() - offset).matrix()), mixture};
}

core::Basis basis_spanning(const core::Basis& basis, const Eigen::VectorXd& junction_c) {
  return core::Basis(basis.terms(), core::TemperatureScaling::spanning(junction_c));
}

void JunctionDynamicsOptions::validate() const {
  if (!(rejection_level > 0.0 && rejection_level < 1.0)) {
    throw core::InvalidInput("junction dynamics: rejection_level must be in (0, 1)");
  }
  if (!(initial_log_step > 0.0) || !(log_tolerance > 0.0) || !(value_tolerance > 0.0)) {
    throw core::InvalidInput("junction dynamics: the search's step and tolerances must be positive");
  }
  if (max_evaluations < kMinEvaluations) {
    throw core::InvalidInput("junction dynamics: max_evaluations must be at least " +
                             std::to_string(kMinEvaluations));
  }
}

std::optional<core::ThermalNoise> held_junction_noise(const core::KalmanNoiseFit& fit) {
  const auto junction = static_cast<std::size_t>(core::KalmanNoiseLevel::kJunctionProcess);
  if (fit.levels[junction].held ||
      !(fit.noise.junction_process_psd_k2_per_s > fit.start.junction_process_psd_k2_per_s)) {
    return std::nullopt;
  }
  core::ThermalNoise held = fit.noise;
  held.junction_process_psd_k2_per_s = fit.start.junction_process_psd_k2_per_s;
  return held;
}

JunctionDynamicsFit fit_junction_dynamics(const JunctionDynamicsProblem& problem,
                                          const JunctionDynamicsOptions& options,
                                          const JunctionDynamicsProgress& progress) {
  options.validate();
  JunctionDynamicsFit fit;
  fit.datasheet = junction_dynamics_of(problem.case_fit.prior);
  fit.case_log_noise = problem.kalman_noise;
  fit.held_junction_noise = problem.held_junction_noise;
  Evaluator evaluator(problem, options, progress);
  const LogDynamics start = log_of(junction_dynamics_of(problem.case_fit.parameters));
  fit.start = evaluator.evaluate(start, true, fit);
  // Where the search starts: the case-log fit's junction, or the same dynamics with q_j held at
  // its start when the ranges reject the case log's q_j (the header).
  JunctionDynamicsPoint search_start = fit.start;
  if (problem.held_junction_noise) {
    evaluator.use_noise(*problem.held_junction_noise);
    const JunctionDynamicsPoint held = evaluator.evaluate(start, false, fit);
    std::tie(fit.noise_block_t, fit.noise_block_p) = block_gain_test(held, fit.start);
    fit.junction_noise_held = fit.noise_block_p < options.rejection_level;
    if (fit.junction_noise_held) {
      search_start = held;
    } else {
      evaluator.use_noise(problem.kalman_noise);
    }
    fit.held_junction_noise_start = held;
  }

  // The box around the datasheet, widened to hold the start. A product of two parameters with
  // independent log-normal priors has √2 times their log standard deviation.
  const LogDynamics centre = log_of(fit.datasheet);
  const double half_width = kSearchPriorSigmas * std::sqrt(2.0) * problem.case_fit_options.prior_log_std;
  const auto low = [&](double c, double s) { return std::min(c - half_width, s); };
  const auto high = [&](double c, double s) { return std::max(c + half_width, s); };

  // Nelder-Mead on the two log coordinates, inside the box: the posterior's ridge (a larger rise
  // with a slower time constant shows alike at a switch) is diagonal, where a search along one
  // coordinate at a time crawls.
  const Eigen::Vector2d box_low(low(centre.log_rise, start.log_rise),
                                low(centre.log_time_constant, start.log_time_constant));
  const Eigen::Vector2d box_high(high(centre.log_rise, start.log_rise),
                                 high(centre.log_time_constant, start.log_time_constant));
  fit.best = search_start;
  const auto negative_posterior = [&](const Eigen::Vector2d& v) {
    const Eigen::Vector2d x = v.cwiseMax(box_low).cwiseMin(box_high);
    const JunctionDynamicsPoint p = evaluator.evaluate({x[0], x[1]}, false, fit);
    if (p.log_posterior() > fit.best.log_posterior()) fit.best = p;
    const double l = p.log_posterior();
    return std::isfinite(l) ? -l : std::numeric_limits<double>::max();
  };
  minimize_nelder_mead(negative_posterior, Eigen::Vector2d(start.log_rise, start.log_time_constant),
                       options, -search_start.log_posterior(), box_low, box_high);
  std::tie(fit.block_t, fit.block_p) = block_gain_test(fit.best, fit.start);
  fit.replaced = fit.block_p < options.rejection_level;
  return fit;
}

}  // namespace tofcomp::calibration
