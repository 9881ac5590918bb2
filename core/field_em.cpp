// EM with one unknown distance per still episode: see field_em.hpp.
#include "core/field_em.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <string>

#include "core/error.hpp"
#include "core/validation.hpp"
#include "core/weighted_least_squares.hpp"

namespace tofcomp::core {
namespace {

// Iterations of train_em that give the field fit its start when none is given: enough for the
// modes to separate, not to converge (the episodes' distances are not yet fitted).
constexpr int kStartIterations = 50;

void validate(const Eigen::Ref<const Eigen::MatrixXd>& h, const Eigen::Ref<const Eigen::VectorXd>& y,
              const std::vector<int>& episode, int episodes, const FieldEmOptions& o) {
  require_same_length(h.rows(), "H (rows)", y.size(), "y");
  require_same_length(static_cast<Eigen::Index>(episode.size()), "the episode indices", y.size(),
                      "y");
  require_finite(h, "H");
  require_finite(y, "y");
  if (o.modes < 1) throw InvalidInput("field EM training needs at least one mode");
  if (episodes < 0) throw InvalidInput("field EM training: a negative number of episodes");
  if (o.max_iterations < 1) throw InvalidInput("field EM training needs max_iterations >= 1");
  if (!(o.log_likelihood_tolerance >= 0.0)) {
    throw InvalidInput("log_likelihood_tolerance must be non-negative");
  }
  if (!(o.min_mode_weight >= 0.0 && o.min_mode_weight < 1.0 / o.modes)) {
    throw InvalidInput("min_mode_weight must be in [0, 1/M)");
  }
  require_finite(o.pinned_mean_offset_mm, "the pinned mean offset");
  std::vector<long> count(static_cast<std::size_t>(episodes), 0);
  for (std::size_t k = 0; k < episode.size(); ++k) {
    const int e = episode[k];
    if (e == kKnownDistance) continue;
    if (e < 0 || e >= episodes) {
      throw InvalidInput("field EM training: range " + std::to_string(k) + " names episode " +
                         std::to_string(e) + ", outside 0.." + std::to_string(episodes - 1));
    }
    ++count[static_cast<std::size_t>(e)];
  }
  for (int e = 0; e < episodes; ++e) {
    if (count[static_cast<std::size_t>(e)] == 0) {
      throw InvalidInput("field EM training: episode " + std::to_string(e) + " has no range");
    }
  }
  if (o.start) require_valid_start(*o.start, h.cols(), o.modes, "field EM training");
  const Eigen::Index parameters = h.cols() + 3 * static_cast<Eigen::Index>(o.modes) - 1 + episodes;
  if (y.size() <= parameters) {
    std::ostringstream msg;
    msg << "field EM training: " << y.size() << " ranges cannot determine " << parameters
        << " parameters (" << h.cols() << " basis columns, " << o.modes << " modes and "
        << episodes << " episode distances)";
    throw InvalidInput(msg.str());
  }
}

// The median of each episode's ranges: subtracted before the fit, so that the normal equations
// hold millimetres of offset, not metres of distance.
Eigen::VectorXd episode_medians(const Eigen::Ref<const Eigen::VectorXd>& y,
                                const std::vector<int>& episode, int episodes) {
  std::vector<std::vector<double>> values(static_cast<std::size_t>(episodes));
  for (std::size_t k = 0; k < episode.size(); ++k) {
    if (episode[k] != kKnownDistance) {
      values[static_cast<std::size_t>(episode[k])].push_back(y[static_cast<Eigen::Index>(k)]);
    }
  }
  Eigen::VectorXd median(episodes);
  for (int e = 0; e < episodes; ++e) {
    auto& v = values[static_cast<std::size_t>(e)];
    const auto middle = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), middle, v.end());
    median[e] = *middle;
  }
  return median;
}

// The fit's parameters, the distances relative to the episodes' medians.
struct FieldParameters {
  Eigen::VectorXd theta;
  MixtureParameters mixture;
  Eigen::VectorXd distance;  // d_e − median_e
};

Eigen::VectorXd residual_of(const Eigen::Ref<const Eigen::MatrixXd>& h,
                            const Eigen::VectorXd& y, const std::vector<int>& episode,
                            const FieldParameters& p) {
  Eigen::VectorXd residual = y - h * p.theta;
  for (std::size_t k = 0; k < episode.size(); ++k) {
    if (episode[k] != kKnownDistance) {
      residual[static_cast<Eigen::Index>(k)] -= p.distance[episode[k]];
    }
  }
  return residual;
}

// The exact M-step with the episodes' distances profiled out. With t_k = Σ_i w_ki and H centred
// on its t-weighted mean H̄ (Hc = H − H̄; μ^c_i = μ_i + H̄θ), the unknowns β = (θ, μ^c) and d have
// the normal equations
//   [N  Aᵀ] [β]   [b]
//   [A  S ] [d] = [r],   S = diag(s_e), s_e = Σ_{k∈e} t_k,
// where row e of A is Σ_{k∈e} (t_k Hc_k, w_k1 .. w_kM) and r_e = Σ_{k∈e} t_k y_k. Eliminating d:
//   (N − Aᵀ S⁻¹ A) β = b − Aᵀ S⁻¹ r,   d = S⁻¹ (r − A β).
// Without a range of known distance the reduced matrix is singular along (θ, μ^c) = (0, 1); the
// pin cᵀβ = Σ π_i μ_i = pinned, c = (−H̄, π), is added as λ c cᵀ: the objective is flat along
// that direction and cᵀ(0, 1) = 1, so the minimizer meets the pin exactly for any λ > 0.
FieldParameters m_step(const Eigen::Ref<const Eigen::MatrixXd>& h, const Eigen::VectorXd& y,
                       const std::vector<int>& episode, int episodes, const Eigen::MatrixXd& r,
                       const Eigen::VectorXd& previous_variance, double floor, bool known_any,
                       double pinned, Eigen::MatrixXd& scratch) {
  const Eigen::Index k = y.size();
  const Eigen::Index p = h.cols();
  const Eigen::Index m = r.cols();
  const Eigen::Index n = p + m;
  const Eigen::MatrixXd w = r * previous_variance.cwiseInverse().asDiagonal();
  const Eigen::VectorXd t = w.rowwise().sum();
  const Eigen::ArrayXd sqrt_t = t.array().sqrt();
  const Eigen::RowVectorXd h_mean = (t.transpose() * h) / t.sum();
  scratch = sqrt_t.matrix().asDiagonal() * (h.rowwise() - h_mean);  // rows √t_k Hc_k

  Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd rhs(n);
  normal.topLeftCorner(p, p) = gram(scratch);
  rhs.head(p) = scratch.transpose() * (sqrt_t * y.array()).matrix();
  normal.topRightCorner(p, m) = scratch.transpose() * (w.array().colwise() / sqrt_t).matrix();
  normal.bottomLeftCorner(m, p) = normal.topRightCorner(p, m).transpose();
  normal.bottomRightCorner(m, m) = w.colwise().sum().transpose().asDiagonal();
  rhs.tail(m) = w.transpose() * y;

  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(episodes, n);
  Eigen::VectorXd s = Eigen::VectorXd::Zero(episodes);
  Eigen::VectorXd target = Eigen::VectorXd::Zero(episodes);
  for (Eigen::Index i = 0; i < k; ++i) {
    const int e = episode[static_cast<std::size_t>(i)];
    if (e == kKnownDistance) continue;
    a.row(e).head(p) += sqrt_t[i] * scratch.row(i);
    a.row(e).tail(m) += w.row(i);
    s[e] += t[i];
    target[e] += t[i] * y[i];
  }
  const Eigen::VectorXd inverse_s = s.cwiseInverse();
  normal.noalias() -= a.transpose() * inverse_s.asDiagonal() * a;
  rhs.noalias() -= a.transpose() * inverse_s.cwiseProduct(target);

  FieldParameters out;
  out.mixture.weight = r.colwise().sum().transpose() / static_cast<double>(k);
  out.mixture.weight /= out.mixture.weight.sum();
  if (!known_any) {
    Eigen::VectorXd c(n);
    c.head(p) = -h_mean.transpose();
    c.tail(m) = out.mixture.weight;
    const double lambda = normal.trace() / static_cast<double>(n);
    normal.noalias() += lambda * c * c.transpose();
    rhs += lambda * pinned * c;
  }
  const Eigen::VectorXd beta =
      solve_normal_equations(normal, rhs, "the normal matrix of the field M-step (θ, μ)");
  out.theta = beta.head(p);
  out.mixture.mean = beta.tail(m).array() - h_mean.dot(out.theta);
  out.distance = inverse_s.cwiseProduct(target - a * beta);

  const Eigen::VectorXd residual = residual_of(h, y, episode, out);
  out.mixture.variance.resize(m);
  for (Eigen::Index i = 0; i < m; ++i) {
    const double mass = r.col(i).sum();
    const double spread =
        r.col(i).dot((residual.array() - out.mixture.mean[i]).square().matrix()) / mass;
    out.mixture.variance[i] = std::max(spread, floor);
  }
  return out;
}

// The start: the given θ and modes with each episode's distance their residuals' mean, or
// train_em's quantile start on the ranges less their episodes' medians.
FieldParameters start_of(const Eigen::Ref<const Eigen::MatrixXd>& h, const Eigen::VectorXd& y,
                         const std::vector<int>& episode, int episodes, const FieldEmOptions& o,
                         double floor) {
  FieldParameters start;
  if (o.start) {
    start.theta = Eigen::VectorXd::Zero(h.cols());
    start.theta.head(o.start->theta.size()) = o.start->theta;
    start.mixture = o.start->mixture;
    start.mixture.variance = start.mixture.variance.cwiseMax(floor);
  } else {
    EmTrainOptions first;
    first.modes = o.modes;
    first.max_iterations = kStartIterations;
    first.weight_tolerance = kWeightRuleOff;
    first.variance_floor = floor;
    first.min_mode_weight = o.min_mode_weight;
    first.record_trace = false;
    const EmTrainResult fit = train_em(h, y, first);
    start.theta = fit.theta;
    start.mixture = fit.mixture;
  }
  // Each episode's distance: its residuals' mean less the modes' mean offset.
  start.distance = Eigen::VectorXd::Zero(episodes);
  const Eigen::VectorXd residual = residual_of(h, y, episode, start);
  Eigen::VectorXd count = Eigen::VectorXd::Zero(episodes);
  for (std::size_t i = 0; i < episode.size(); ++i) {
    if (episode[i] == kKnownDistance) continue;
    start.distance[episode[i]] += residual[static_cast<Eigen::Index>(i)];
    count[episode[i]] += 1.0;
  }
  start.distance = start.distance.cwiseQuotient(count).array() - start.mixture.mean_offset();
  return start;
}

}  // namespace

FieldEmResult train_field_em(const Eigen::Ref<const Eigen::MatrixXd>& h,
                             const Eigen::Ref<const Eigen::VectorXd>& y,
                             const std::vector<int>& episode, int episodes,
                             const FieldEmOptions& options) {
  validate(h, y, episode, episodes, options);
  const Eigen::VectorXd median = episode_medians(y, episode, episodes);
  Eigen::VectorXd relative = y;  // y less its episode's median; y − d where d is known
  bool known_any = false;
  for (std::size_t k = 0; k < episode.size(); ++k) {
    if (episode[k] == kKnownDistance) {
      known_any = true;
    } else {
      relative[static_cast<Eigen::Index>(k)] -= median[episode[k]];
    }
  }
  const double spread = (relative.array() - relative.mean()).square().mean();
  const double floor = std::max(options.variance_floor, kRelativeVarianceFloor * spread);

  FieldParameters point = start_of(h, relative, episode, episodes, options, floor);
  Eigen::MatrixXd r;
  Eigen::MatrixXd scratch;
  FieldEmResult result;
  double previous = -std::numeric_limits<double>::infinity();
  for (;;) {
    const double log_likelihood =
        mixture_e_step(residual_of(h, relative, episode, point), point.mixture, r);
    result.log_likelihood = log_likelihood;
    if (std::abs(log_likelihood - previous) <=
        options.log_likelihood_tolerance * static_cast<double>(y.size())) {
      result.converged = true;
      break;
    }
    if (result.iterations >= options.max_iterations) break;
    require_modes_populated(r, options.min_mode_weight, result.iterations + 1,
                            "field EM training");
    previous = log_likelihood;
    point = m_step(h, relative, episode, episodes, r, point.mixture.variance, floor, known_any,
                   options.pinned_mean_offset_mm, scratch);
    ++result.iterations;
  }

  // Modes by increasing mean, so that a result does not depend on label switching.
  std::vector<int> order(static_cast<std::size_t>(options.modes));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return point.mixture.mean[a] < point.mixture.mean[b];
  });
  result.mixture.mean.resize(options.modes);
  result.mixture.variance.resize(options.modes);
  result.mixture.weight.resize(options.modes);
  for (int i = 0; i < options.modes; ++i) {
    const int from = order[static_cast<std::size_t>(i)];
    result.mixture.mean[i] = point.mixture.mean[from];
    result.mixture.variance[i] = point.mixture.variance[from];
    result.mixture.weight[i] = point.mixture.weight[from];
  }
  result.theta = point.theta;
  result.episode_distance = point.distance + median;
  result.distance_determined = known_any;
  return result;
}

}  // namespace tofcomp::core
