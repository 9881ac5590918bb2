#include "core/em_train.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <sstream>

#include "core/error.hpp"
#include "core/mixture_sweep.hpp"
#include "core/mode_regression.hpp"
#include "core/squarem.hpp"
#include "core/validation.hpp"
#include "core/weighted_least_squares.hpp"

namespace tofcomp::core {
namespace {

struct MStepResult {
  Eigen::VectorXd theta;
  MixtureParameters mixture;
};

// σ_i² and π_i given θ, μ and the responsibilities (the closed-form part of Eq. 19).
// When subtract_mean is false σ_i² is the weighted second moment of e, as Eq. 19 prints it.
void update_variances_and_weights(const Eigen::VectorXd& residual, const Eigen::MatrixXd& r,
                                  double floor, bool subtract_mean, MixtureParameters& m) {
  const Eigen::Index k = residual.size();
  m.variance.resize(m.mean.size());
  m.weight.resize(m.mean.size());
  for (int i = 0; i < m.modes(); ++i) {
    const double mass = r.col(i).sum();
    const double centre = subtract_mean ? m.mean[i] : 0.0;
    const double second_moment = r.col(i).dot((residual.array() - centre).square().matrix()) / mass;
    m.variance[i] = std::max(second_moment, floor);
    m.weight[i] = mass / static_cast<double>(k);
  }
  m.weight /= m.weight.sum();
}

// Exact (ECM) M-step: maximizes Σ_k Σ_i r_ki [−(ỹ_k − H_k θ − μ_i)² / (2σ_i²)] jointly over
// (θ, μ) with the previous σ² (core/mode_regression.hpp), then σ² and π in closed form.
MStepResult exact_m_step(const Eigen::Ref<const Eigen::MatrixXd>& h, const Eigen::VectorXd& y,
                         const Eigen::MatrixXd& r, const Eigen::VectorXd& previous_variance,
                         double floor, Eigen::MatrixXd& scratch) {
  const Eigen::MatrixXd w = r * previous_variance.cwiseInverse().asDiagonal();  // K × M
  BiasAndOffsets solved = solve_bias_and_offsets(h, y, w, scratch);
  MStepResult out;
  out.theta = std::move(solved.theta);
  out.mixture.mean = std::move(solved.mean);
  const Eigen::VectorXd residual = y - h * out.theta;
  update_variances_and_weights(residual, r, floor, true, out.mixture);
  return out;
}

// Eq. 19 exactly as printed (see the header for where it departs from a maximization).
MStepResult paper_m_step(const Eigen::Ref<const Eigen::MatrixXd>& h, const Eigen::VectorXd& y,
                         const Eigen::MatrixXd& r, const Eigen::VectorXd& previous_variance,
                         double floor, Eigen::MatrixXd& scratch) {
  const Eigen::VectorXd c_diagonal = r * previous_variance;  // C = σ_1² Σ_1 + σ_2² Σ_2
  const Eigen::VectorXd c_inverse = c_diagonal.cwiseInverse();
  const Eigen::MatrixXd g = weighted_gram(h, c_inverse, scratch);
  const Eigen::VectorXd b = h.transpose() * c_inverse.cwiseProduct(y);

  MStepResult out;
  out.theta = solve_normal_equations(g, b, "HᵀC⁻¹H of Eq. 19");
  const Eigen::VectorXd residual = y - h * out.theta;
  const Eigen::VectorXd mass = r.colwise().sum().transpose();
  out.mixture.mean = ((r.transpose() * residual).array() / mass.array()).matrix();
  update_variances_and_weights(residual, r, floor, false, out.mixture);
  return out;
}

// Eq. 20.
MStepResult paper_initialization(Eigen::Index columns) {
  MStepResult init;
  init.theta = Eigen::VectorXd::Zero(columns);
  init.mixture.mean = Eigen::Vector2d(0.1, -0.1);
  init.mixture.variance = Eigen::Vector2d(0.1, 0.1);
  init.mixture.weight = Eigen::Vector2d(0.5, 0.5);
  return init;
}

// θ and a constant by ordinary least squares (the exact M-step with one mode and unit
// weights); the residual's M quantile groups give μ_i and σ_i².
MStepResult quantile_initialization(const Eigen::Ref<const Eigen::MatrixXd>& h,
                                    const Eigen::VectorXd& y, int modes, double floor,
                                    Eigen::MatrixXd& scratch) {
  const Eigen::Index k = y.size();
  const MStepResult ls =
      exact_m_step(h, y, Eigen::MatrixXd::Ones(k, 1), Eigen::VectorXd::Ones(1), floor, scratch);
  std::vector<double> residual(static_cast<std::size_t>(k));
  Eigen::Map<Eigen::VectorXd>(residual.data(), k) = y - h * ls.theta;
  std::sort(residual.begin(), residual.end());

  MStepResult init;
  init.theta = ls.theta;
  init.mixture.mean.resize(modes);
  init.mixture.variance.resize(modes);
  init.mixture.weight = Eigen::VectorXd::Constant(modes, 1.0 / modes);
  for (int i = 0; i < modes; ++i) {
    const auto begin = residual.begin() + static_cast<std::ptrdiff_t>(k * i / modes);
    const auto end = residual.begin() + static_cast<std::ptrdiff_t>(k * (i + 1) / modes);
    const double n = static_cast<double>(end - begin);
    const double mean = std::accumulate(begin, end, 0.0) / n;
    double spread = 0.0;
    for (auto it = begin; it != end; ++it) spread += (*it - mean) * (*it - mean);
    init.mixture.mean[i] = mean;
    init.mixture.variance[i] = std::max(spread / n, floor);
  }
  return init;
}

// A warm start: θ padded with zeros to H's columns, the variances kept at or above the floor.
MStepResult given_start(const EmStartingPoint& start, Eigen::Index columns, double floor) {
  MStepResult init;
  init.theta = Eigen::VectorXd::Zero(columns);
  init.theta.head(start.theta.size()) = start.theta;
  init.mixture = start.mixture;
  init.mixture.variance = init.mixture.variance.cwiseMax(floor);
  return init;
}


void validate_arguments(const Eigen::Ref<const Eigen::MatrixXd>& h,
                        const Eigen::Ref<const Eigen::VectorXd>& y, const EmTrainOptions& o) {
  require_same_length(h.rows(), "H (rows)", y.size(), "y - d");
  require_finite(h, "H");
  require_finite(y, "y - d");
  if (o.modes < 1) throw InvalidInput("EM training needs at least one mode");
  if (o.initialization == EmInitialization::Paper && o.modes != 2) {
    throw InvalidInput("the paper's initial conditions (Eq. 20) are defined for two modes only");
  }
  if (o.max_iterations < 1) throw InvalidInput("EM training needs max_iterations >= 1");
  if (!(o.weight_tolerance > 0.0)) throw InvalidInput("weight_tolerance must be positive");
  if (!(o.log_likelihood_tolerance >= 0.0)) {
    throw InvalidInput("log_likelihood_tolerance must be non-negative");
  }
  if (!(o.min_mode_weight >= 0.0 && o.min_mode_weight < 1.0 / o.modes)) {
    throw InvalidInput("min_mode_weight must be in [0, 1/M)");
  }
  if (o.start) require_valid_start(*o.start, h.cols(), o.modes, "EM training");
  const Eigen::Index parameters = h.cols() + 3 * static_cast<Eigen::Index>(o.modes) - 1;
  if (y.size() <= parameters) {
    std::ostringstream msg;
    msg << "EM training: " << y.size() << " samples cannot determine " << parameters
        << " parameters (" << h.cols() << " basis columns and " << o.modes << " modes); at least "
        << parameters + 1 << " are needed";
    throw InvalidInput(msg.str());
  }
}

// Orders the modes by increasing mean, so that results do not depend on label switching.
void sort_modes(EmTrainResult& result) {
  const int m = result.mixture.modes();
  std::vector<int> order(static_cast<std::size_t>(m));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return result.mixture.mean[a] < result.mixture.mean[b]; });
  auto permute = [&](const Eigen::VectorXd& v) {
    Eigen::VectorXd out(m);
    for (int i = 0; i < m; ++i) out[i] = v[order[static_cast<std::size_t>(i)]];
    return out;
  };
  result.mixture.mean = permute(result.mixture.mean);
  result.mixture.variance = permute(result.mixture.variance);
  result.mixture.weight = permute(result.mixture.weight);
  Eigen::MatrixXd r(result.responsibilities.rows(), m);
  for (int i = 0; i < m; ++i)
    r.col(i) = result.responsibilities.col(order[static_cast<std::size_t>(i)]);
  result.responsibilities = std::move(r);
  for (auto& record : result.trace) {
    record.mean = permute(record.mean);
    record.variance = permute(record.variance);
    record.weight = permute(record.weight);
  }
}

// The parameters as one vector in which every point is a valid mixture (core/squarem.hpp):
// θ, μ, log σ², log(π_i / π_M) for i < M.
Eigen::VectorXd encode(const MStepResult& x) {
  const Eigen::Index p = x.theta.size();
  const int m = x.mixture.modes();
  Eigen::VectorXd v(p + 3 * m - 1);
  v.head(p) = x.theta;
  v.segment(p, m) = x.mixture.mean;
  v.segment(p + m, m) = x.mixture.variance.array().log().matrix();
  const double last = std::log(x.mixture.weight[m - 1]);
  v.tail(m - 1) = (x.mixture.weight.head(m - 1).array().log() - last).matrix();
  return v;
}

// The inverse of encode, the variances kept at or above the floor. Empty when a coordinate is
// not finite.
std::optional<MStepResult> decode(const Eigen::VectorXd& v, Eigen::Index p, int m, double floor) {
  if (!v.allFinite()) return std::nullopt;
  MStepResult x;
  x.theta = v.head(p);
  x.mixture.mean = v.segment(p, m);
  x.mixture.variance = v.segment(p + m, m).array().exp().max(floor).matrix();
  Eigen::VectorXd log_ratio(m);
  log_ratio.head(m - 1) = v.tail(m - 1);
  log_ratio[m - 1] = 0.0;
  const Eigen::ArrayXd w = (log_ratio.array() - log_ratio.maxCoeff()).exp();
  x.mixture.weight = (w / w.sum()).matrix();
  if (!x.mixture.variance.allFinite()) return std::nullopt;
  return x;
}

bool modes_populated(const Eigen::MatrixXd& r, double min_weight) {
  const double k = static_cast<double>(r.rows());
  return ((r.colwise().sum().array() / k) >= min_weight).all();
}

// A point of the iteration: parameters, and the E-step at them (with the exact step's sums).
struct EmIterate {
  MStepResult parameters;
  Eigen::MatrixXd responsibilities;
  double log_likelihood = 0.0;
  ExactStepSums sums;
};

// The iteration's bookkeeping: the point it stands at, the stopping rule, the trace.
class Iteration {
 public:
  Iteration(const EmTrainOptions& options, Eigen::Index k, EmTrainResult& result)
      : options_(options), k_(static_cast<double>(k)), result_(result) {}

  // Moves to `next` (its E-step done) and records it.
  void arrive(EmIterate&& next) {
    if (has_point_) {
      weight_change_ =
          (next.parameters.mixture.weight - point_.parameters.mixture.weight).cwiseAbs().maxCoeff();
      previous_log_likelihood_ = point_.log_likelihood;
    }
    point_ = std::move(next);
    has_point_ = true;
    if (options_.record_trace) {
      const MixtureParameters& m = point_.parameters.mixture;
      result_.trace.push_back({m.mean, m.variance, m.weight, point_.log_likelihood});
    }
  }
  // The paper's rule on the weights, and the log-likelihood's change per range.
  bool converged() const {
    const bool likelihood_settled =
        options_.log_likelihood_tolerance == 0.0 ||
        std::abs(point_.log_likelihood - previous_log_likelihood_) <=
            options_.log_likelihood_tolerance * k_;
    return weight_change_ < options_.weight_tolerance && likelihood_settled;
  }
  bool at_cap() const { return result_.iterations >= options_.max_iterations; }
  // Stops when converged or at the iteration cap.
  bool done() {
    if (converged()) {
      result_.converged = true;
      return true;
    }
    return at_cap();
  }
  const EmIterate& point() const { return point_; }
  EmIterate take() { return std::move(point_); }

 private:
  const EmTrainOptions& options_;
  double k_;
  EmTrainResult& result_;
  EmIterate point_;
  bool has_point_ = false;
  double previous_log_likelihood_ = -std::numeric_limits<double>::infinity();
  double weight_change_ = std::numeric_limits<double>::infinity();
};

}  // namespace

void require_modes_populated(const Eigen::MatrixXd& r, double min_weight, int iteration,
                             const std::string& fit) {
  const double k = static_cast<double>(r.rows());
  for (Eigen::Index i = 0; i < r.cols(); ++i) {
    const double weight = r.col(i).sum() / k;
    if (!(weight >= min_weight)) {
      std::ostringstream msg;
      msg << fit << ": at iteration " << iteration << " mode " << i + 1 << " of " << r.cols()
          << " holds a fraction " << weight << " of the samples (minimum " << min_weight
          << "): the data do not show " << r.cols() << " distinct lasing modes; train with fewer "
          << "modes";
      throw EmptiedModeError(msg.str(), static_cast<int>(i));
    }
  }
}

void require_valid_start(const EmStartingPoint& start, Eigen::Index columns, int modes,
                         const std::string& fit) {
  if (start.theta.size() > columns) {
    throw InvalidInput(fit + ": the starting θ has more entries than H has columns");
  }
  if (start.mixture.modes() != modes) {
    throw InvalidInput(fit + ": the starting mixture's mode count differs from `modes`");
  }
  start.mixture.validate();
  require_finite(start.theta, "the starting θ");
}

EmTrainResult train_em(const Eigen::Ref<const Eigen::MatrixXd>& h,
                       const Eigen::Ref<const Eigen::VectorXd>& y_minus_d,
                       const EmTrainOptions& options) {
  validate_arguments(h, y_minus_d, options);
  const Eigen::VectorXd y = y_minus_d;
  const Eigen::Index k = y.size();
  const double variance = (y.array() - y.mean()).square().sum() / static_cast<double>(k);
  if (!(variance > 0.0)) {
    throw NumericalError(
        "EM training: the ranges minus the distance have zero variance; a "
        "mixture of lasing modes cannot be fitted to constant data");
  }
  const double floor = std::max(options.variance_floor, kRelativeVarianceFloor * variance);

  Eigen::MatrixXd scratch;
  MStepResult current = options.start                ? given_start(*options.start, h.cols(), floor)
                        : options.initialization == EmInitialization::Paper
                            ? paper_initialization(h.cols())
                            : quantile_initialization(h, y, options.modes, floor, scratch);

  EmTrainResult result;
  const bool exact = options.m_step == MStep::Exact;
  // H is centred on the weighted mean of the last sweep (any centre gives the same step).
  Eigen::RowVectorXd centre = h.colwise().mean();
  const auto evaluate = [&](MStepResult parameters) {
    EmIterate out;
    out.parameters = std::move(parameters);
    // E-step (Eq. 18) at the parameters; for the exact step fused with its weighted sums.
    if (exact) {
      out.sums = exact_step_sweep(h, y, out.parameters.theta, out.parameters.mixture, centre,
                                  out.responsibilities, options.parallel_for);
      out.log_likelihood = out.sums.log_likelihood;
      centre = out.sums.weighted_mean();
    } else {
      out.log_likelihood = mixture_e_step(y - h * out.parameters.theta, out.parameters.mixture,
                                          out.responsibilities);
    }
    ++result.likelihood_evaluations;
    return out;
  };
  // M-step (Eq. 19) from a point whose E-step is done.
  const auto step = [&](const EmIterate& from) {
    require_modes_populated(from.responsibilities, options.min_mode_weight, result.iterations + 1,
                            "EM training");
    ++result.iterations;
    if (!exact) {
      return paper_m_step(h, y, from.responsibilities, from.parameters.mixture.variance, floor,
                          scratch);
    }
    MStepResult next;
    exact_step_solve(h, y, from.sums, from.responsibilities, floor, next.theta, next.mixture,
                     options.parallel_for);
    return next;
  };

  Iteration iteration(options, k, result);
  iteration.arrive(evaluate(std::move(current)));
  const bool accelerate = options.acceleration == EmAcceleration::Squarem && exact;
  SquaremSteps steps;
  const Eigen::Index p = h.cols();
  const int modes = options.modes;
  while (!iteration.done()) {
    if (!accelerate) {
      iteration.arrive(evaluate(step(iteration.point())));
      continue;
    }
    // SQUAREM: two EM steps x0 → x1 → x2, then the extrapolated point, kept when valid and not
    // below x1's log-likelihood; x2 otherwise.
    const Eigen::VectorXd x0 = encode(iteration.point().parameters);
    iteration.arrive(evaluate(step(iteration.point())));
    if (iteration.done()) break;
    const Eigen::VectorXd x1 = encode(iteration.point().parameters);
    const double x1_log_likelihood = iteration.point().log_likelihood;
    MStepResult x2 = step(iteration.point());
    const Eigen::VectorXd r = x1 - x0;
    const Eigen::VectorXd v = encode(x2) - x1 - r;
    const double alpha = steps.step_length(r, v);
    if (alpha > 1.0) {
      if (std::optional<MStepResult> jump =
              decode(SquaremSteps::extrapolate(x0, r, v, alpha), p, modes, floor)) {
        std::optional<EmIterate> tried;
        try {
          tried = evaluate(std::move(*jump));
        } catch (const NumericalError&) {
          // A non-finite likelihood at the extrapolated point: refused below.
        }
        if (tried && tried->log_likelihood >= x1_log_likelihood &&
            modes_populated(tried->responsibilities, options.min_mode_weight)) {
          steps.accepted(alpha);
          iteration.arrive(std::move(*tried));
          continue;
        }
      }
      steps.refused(alpha);
    } else {
      steps.accepted(alpha);
    }
    iteration.arrive(evaluate(std::move(x2)));
  }
  EmIterate last = iteration.take();
  result.log_likelihood = last.log_likelihood;
  result.responsibilities = std::move(last.responsibilities);
  current = std::move(last.parameters);
  result.theta = std::move(current.theta);
  result.mixture = std::move(current.mixture);
  if (options.sort_modes) sort_modes(result);
  return result;
}

}  // namespace tofcomp::core
