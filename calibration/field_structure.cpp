#include "calibration/field_structure.hpp"

#include <cmath>
#include <limits>
#include <optional>

#include "calibration/measured_data.hpp"
#include "core/error.hpp"

namespace tofcomp::calibration {
namespace {

// One fold's part of the ranges: the rows taken, their episodes renumbered over those present.
struct FoldPart {
  std::vector<Eigen::Index> rows;
  std::vector<int> episode;
  int episodes = 0;
  std::vector<int> renumbered;  // original episode → this part's, or −2 when absent
};

constexpr int kAbsent = -2;

FoldPart part_of(const std::vector<int>& episode, int episodes, const std::vector<bool>& in_fold) {
  FoldPart p;
  p.renumbered.assign(static_cast<std::size_t>(episodes), kAbsent);
  for (std::size_t k = 0; k < episode.size(); ++k) {
    if (!in_fold[k]) continue;
    int e = episode[k];
    if (e != core::kKnownDistance) {
      int& number = p.renumbered[static_cast<std::size_t>(e)];
      if (number == kAbsent) number = p.episodes++;
      e = number;
    }
    p.rows.push_back(static_cast<Eigen::Index>(k));
    p.episode.push_back(e);
  }
  return p;
}

// Σ log P(rounded range) over the scoring fold's ranges whose episode the fit saw, and how many.
std::pair<double, long> score(const core::FieldEmResult& fit, const FoldPart& fitted,
                              const Eigen::MatrixXd& h, const Eigen::Ref<const Eigen::VectorXd>& y,
                              const std::vector<int>& episode, const std::vector<bool>& scored) {
  std::vector<Eigen::Index> rows;
  std::vector<double> distance;
  for (std::size_t k = 0; k < episode.size(); ++k) {
    if (!scored[k]) continue;
    const int e = episode[k];
    if (e == core::kKnownDistance) {
      rows.push_back(static_cast<Eigen::Index>(k));
      distance.push_back(0.0);
    } else if (fitted.renumbered[static_cast<std::size_t>(e)] != kAbsent) {
      rows.push_back(static_cast<Eigen::Index>(k));
      distance.push_back(fit.episode_distance[fitted.renumbered[static_cast<std::size_t>(e)]]);
    }
  }
  if (rows.empty()) return {0.0, 0};
  const Eigen::Map<const Eigen::VectorXd> d(distance.data(), static_cast<Eigen::Index>(rows.size()));
  const Eigen::VectorXd residual = y(rows) - d - h(rows, Eigen::all) * fit.theta;
  return {core::rounded_mixture_log_probabilities(residual, fit.mixture, kRangeResolutionMm).sum(),
          static_cast<long>(rows.size())};
}

}  // namespace

FieldBasisChoice choose_field_basis(const Eigen::Ref<const Eigen::VectorXd>& junction_c,
                                    const Eigen::Ref<const Eigen::VectorXd>& y,
                                    const std::vector<int>& episode, int episodes,
                                    const Eigen::Ref<const Eigen::VectorXd>& time_s,
                                    const core::FieldEmOptions& em, const core::Basis& bench) {
  std::vector<bool> first(episode.size()), second(episode.size());
  for (std::size_t k = 0; k < episode.size(); ++k) {
    first[k] = static_cast<long>(std::floor(time_s[static_cast<Eigen::Index>(k)] /
                                            kFieldFoldBlockS)) % 2 == 0;
    second[k] = !first[k];
  }
  const FoldPart a = part_of(episode, episodes, first);
  const FoldPart b = part_of(episode, episodes, second);
  const core::TemperatureScaling scaling = core::TemperatureScaling::spanning(junction_c);
  // The held-out log-likelihood per scored range of a basis; nullopt when a fit finds it beyond
  // what the temperatures met determine (a singular system) or nothing could be scored.
  const auto held_out = [&](const core::Basis& basis) -> std::optional<double> {
    const Eigen::MatrixXd h = basis.design_matrix(junction_c);
    double total = 0.0;
    long scored = 0;
    try {
      for (const auto& [fit_part, score_mask] : {std::pair{&a, &second}, std::pair{&b, &first}}) {
        const core::FieldEmResult fit =
            core::train_field_em(h(fit_part->rows, Eigen::all), y(fit_part->rows),
                                 fit_part->episode, fit_part->episodes, em);
        const auto [sum, count] = score(fit, *fit_part, h, y, episode, *score_mask);
        total += sum;
        scored += count;
      }
    } catch (const core::NumericalError&) {
      return std::nullopt;
    }
    if (scored == 0) return std::nullopt;
    return total / static_cast<double>(scored);
  };
  FieldBasisChoice choice;
  double best = -std::numeric_limits<double>::infinity();
  const auto consider = [&](const core::Basis& basis, double score) {
    choice.held_out.emplace_back(basis.describe(), score);
    if (score <= best) return false;
    best = score;
    choice.basis = basis;
    return true;
  };
  int since_best = 0;
  for (int order = 1; order <= kFieldMaxOrder && since_best < kFieldOrderPatience; ++order) {
    const core::Basis basis({core::BasisTerm{core::BasisKind::Polynomial, order}}, scaling);
    const std::optional<double> score = held_out(basis);
    if (!score) break;
    since_best = consider(basis, *score) ? 0 : since_best + 1;
  }
  const std::vector<core::BasisTerm>& terms = bench.terms();
  const bool one_legendre = terms.size() == 1 && terms[0].kind == core::BasisKind::Polynomial &&
                            terms[0].form == core::PolynomialForm::Legendre;
  if (!one_legendre) {
    const core::Basis own(terms, scaling);
    if (const std::optional<double> score = held_out(own)) consider(own, *score);
  }
  if (choice.held_out.empty()) {
    throw core::NumericalError(
        "field training: no basis could be fitted on held-out time blocks of these records");
  }
  return choice;
}

}  // namespace tofcomp::calibration
