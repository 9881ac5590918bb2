#include "core/residual_statistics.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cmath>
#include <limits>
#include <utility>

#include "core/error.hpp"
#include "core/validation.hpp"
#include "core/warm_up.hpp"

namespace tofcomp::core {
namespace {

constexpr int kTemperatureBins = 4;

// The quartile of each temperature (0..3) by rank.
Eigen::VectorXi quartiles(const Eigen::VectorXd& rank) {
  const auto n = static_cast<double>(rank.size());
  Eigen::VectorXi bin(rank.size());
  for (Eigen::Index k = 0; k < rank.size(); ++k) {
    bin[k] = static_cast<int>(rank[k] * kTemperatureBins / n);
  }
  return bin;
}

// x − x̄ scaled to unit norm, so that a correlation with it is one dot product; zero when x has
// no spread (no correlation can be measured against a constant).
Eigen::VectorXd unit_centred(const Eigen::Ref<const Eigen::VectorXd>& x) {
  Eigen::VectorXd c = x.array() - x.mean();
  const double norm = c.norm();
  if (norm > 0.0) {
    c /= norm;
  } else {
    c.setZero();
  }
  return c;
}

}  // namespace

Eigen::VectorXd ranks(const Eigen::Ref<const Eigen::VectorXd>& v) {
  // An LSD radix sort of 32-bit keys, each above its position in one 64-bit word: radix sorting
  // is stable, so equal keys keep their positions' order. The key is the value as a float, its
  // bits turned so that their unsigned order is the numbers' (sign bit set for positives, all
  // bits flipped for negatives); values that round to one float tie, broken by position. Three
  // passes of 11 bits, where a comparison sort took half of the diagnosis's draws.
  constexpr int kDigitBits = 11;
  constexpr int kPasses = 3;  // 33 bits ≥ the key's 32
  constexpr std::uint32_t kDigits = 1u << kDigitBits;
  if (static_cast<std::uint64_t>(v.size()) > 0xffffffffu) {
    throw InvalidInput("ranks of more than 2^32 values");
  }
  const auto n = static_cast<std::size_t>(v.size());
  std::vector<std::uint64_t> words(n), sorted(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto value = static_cast<float>(v[static_cast<Eigen::Index>(i)]);
    std::uint32_t bits = std::bit_cast<std::uint32_t>(value);
    bits = (bits & 0x80000000u) ? ~bits : (bits | 0x80000000u);
    words[i] = (static_cast<std::uint64_t>(bits) << 32) | static_cast<std::uint64_t>(i);
  }
  for (int pass = 0; pass < kPasses; ++pass) {
    const int shift = 32 + pass * kDigitBits;
    std::vector<std::size_t> start(kDigits + 1, 0);
    for (const std::uint64_t w : words) ++start[((w >> shift) & (kDigits - 1)) + 1];
    for (std::uint32_t d = 0; d < kDigits; ++d) start[d + 1] += start[d];
    for (const std::uint64_t w : words) sorted[start[(w >> shift) & (kDigits - 1)]++] = w;
    words.swap(sorted);
  }
  Eigen::VectorXd r(v.size());
  for (std::size_t i = 0; i < n; ++i) {
    r[static_cast<Eigen::Index>(words[i] & 0xffffffffu)] = static_cast<double>(i);
  }
  return r;
}

ModeAssignment assign_modes(const Eigen::Ref<const Eigen::VectorXd>& residual,
                            const MixtureParameters& mixture) {
  const int modes = mixture.modes();
  // log π_i − log σ_i − (r − μ_i)² / 2σ_i²: the argmax of Eq. 18's weights, without the
  // exponentials.
  Eigen::ArrayXd log_prior(modes), inverse_sd(modes);
  for (int i = 0; i < modes; ++i) {
    log_prior[i] = std::log(mixture.weight[i]) - 0.5 * std::log(mixture.variance[i]);
    inverse_sd[i] = 1.0 / std::sqrt(mixture.variance[i]);
  }
  ModeAssignment out;
  out.mode.resize(residual.size());
  out.compensated.resize(residual.size());
  out.standardized.resize(residual.size());
  for (Eigen::Index k = 0; k < residual.size(); ++k) {
    int best = 0;
    double best_score = -std::numeric_limits<double>::infinity();
    for (int i = 0; i < modes; ++i) {
      const double z = (residual[k] - mixture.mean[i]) * inverse_sd[i];
      const double score = log_prior[i] - 0.5 * z * z;
      if (score > best_score) best_score = score, best = i;
    }
    out.mode[k] = best;
    out.compensated[k] = residual[k] - mixture.mean[best];
    out.standardized[k] = out.compensated[k] * inverse_sd[best];
  }
  return out;
}

ResidualTestDesign::ResidualTestDesign(const Eigen::Ref<const Eigen::VectorXd>& time_s,
                                       const Eigen::Ref<const Eigen::VectorXd>& junction_c,
                                       const Eigen::Ref<const Eigen::VectorXd>& junction_rate_c_per_s,
                                       const Eigen::Ref<const Eigen::VectorXd>& time_since_power_on_s,
                                       const MixtureParameters& mixture, int ljung_box_lags)
    : mixture_(mixture), lags_(ljung_box_lags) {
  const Eigen::Index n = junction_c.size();
  require_same_length(time_s.size(), "time", n, "junction temperature");
  require_same_length(junction_rate_c_per_s.size(), "junction rate", n, "junction temperature");
  require_same_length(time_since_power_on_s.size(), "time since power-on", n,
                      "junction temperature");
  mixture_.validate();
  if (lags_ < 1 || lags_ >= n) throw InvalidInput("Ljung-Box needs 1 <= lags < n");
  const Eigen::VectorXd junction_ranks = ranks(junction_c);
  temperature_quartile_ = quartiles(junction_ranks);
  junction_rank_ = unit_centred(junction_ranks);
  const Eigen::MatrixXd warm_up = warm_up_covariates(time_since_power_on_s);
  correlates_.resize(n, 2 + warm_up.cols());
  correlates_.col(0) = unit_centred(junction_rate_c_per_s);
  correlates_.col(1) = unit_centred(time_s);
  for (Eigen::Index c = 0; c < warm_up.cols(); ++c) {
    correlates_.col(2 + c) = unit_centred(warm_up.col(c));
  }
}

ResidualStatistics ResidualTestDesign::statistics(const Eigen::Ref<const Eigen::VectorXd>& residual,
                                                  ModeAssignment* assignment) const {
  const Eigen::Index n = size();
  require_same_length(residual.size(), "residual", n, "the tests' covariates");
  ModeAssignment a = assign_modes(residual, mixture_);
  ResidualStatistics s;
  const int modes = mixture_.modes();
  if (modes >= 2) {
    const Eigen::VectorXi first = (a.mode.array() == 0).cast<int>();
    if (first.sum() >= 2 && n - first.sum() >= 2) s.runs = runs_test(first);
    Eigen::MatrixXd table = Eigen::MatrixXd::Zero(kTemperatureBins, modes);
    for (Eigen::Index k = 0; k < n; ++k) table(temperature_quartile_[k], a.mode[k]) += 1.0;
    s.weights = chi_square_independence(table);
  }
  // Spearman's ρ: the ranks of |z| against the junction's, which are centred (so the ranks of
  // |z| need no centring) and of unit norm; the ranks' squared norm about their mean (n − 1)/2 is
  // n(n² − 1)/12.
  const double count = static_cast<double>(n);
  const double rank_norm = std::sqrt(count * (count * count - 1.0) / 12.0);
  s.spread = correlation_result(junction_rank_.dot(ranks(a.standardized.cwiseAbs())) / rank_norm, n);
  // Pearson's r of e with each correlate: the correlates are centred, so e need only be scaled.
  const double e_norm = (a.compensated.array() - a.compensated.mean()).matrix().norm();
  const Eigen::VectorXd r =
      e_norm > 0.0 ? Eigen::VectorXd(correlates_.transpose() * a.compensated / e_norm)
                   : Eigen::VectorXd::Zero(correlates_.cols());
  s.heating = correlation_result(r[0], n);
  s.drift = correlation_result(r[1], n);
  for (Eigen::Index c = 2; c < r.size(); ++c) s.warm_up.push_back(correlation_result(r[c], n));
  s.ljung_box = ljung_box(a.compensated, lags_);
  if (assignment) *assignment = std::move(a);
  return s;
}

}  // namespace tofcomp::core
