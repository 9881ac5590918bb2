#include "calibration/model_spec.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/error.hpp"

namespace tofcomp::calibration {
namespace {

// The outlier component starts with this weight, and (from its second start) with the modes of
// the residuals once this share is cut from each tail, so that a broad mode that held the
// outliers does not survive into its fit.
constexpr double kOutlierStartWeight = 0.02;
constexpr double kOutlierTrimFraction = 0.02;
// A split mode's halves start this far apart (in its standard deviation) and this much narrower.
constexpr double kSplitHalfDistance = 0.5;
constexpr double kSplitVarianceShare = 0.75;
// The most modes the search may add to those training chose.
constexpr int kMaxExtraModes = 2;
// Where a chain starts: A = s I + (1 − s) 1 πᵀ (s = ½: half way between independent draws and
// a mode that never changes).
constexpr double kChainStartStay = 0.5;
// Directions of the centred basis below this share of the largest are dropped from Q.
constexpr double kRetainedDirection = 1e-10;

Eigen::MatrixXd append_columns(const Eigen::MatrixXd& left, const Eigen::MatrixXd& right) {
  if (left.size() == 0) return right;
  Eigen::MatrixXd out(left.rows(), left.cols() + right.cols());
  out << left, right;
  return out;
}

Eigen::VectorXd append_zeros(const Eigen::VectorXd& v, Eigen::Index n) {
  Eigen::VectorXd out = Eigen::VectorXd::Zero(v.size() + n);
  out.head(v.size()) = v;
  return out;
}

// M modes of the residuals once their tails are cut: equal-count groups of the sorted rest.
core::MixtureParameters trimmed_quantile_modes(const Eigen::VectorXd& residual, int modes,
                                               double floor) {
  std::vector<double> sorted(residual.data(), residual.data() + residual.size());
  std::sort(sorted.begin(), sorted.end());
  const auto cut =
      static_cast<std::size_t>(kOutlierTrimFraction * static_cast<double>(sorted.size()));
  const std::vector<double> kept(sorted.begin() + static_cast<std::ptrdiff_t>(cut),
                                 sorted.end() - static_cast<std::ptrdiff_t>(cut));
  core::MixtureParameters m;
  m.mean.resize(modes);
  m.variance.resize(modes);
  m.weight = Eigen::VectorXd::Constant(modes, 1.0 / modes);
  const std::size_t n = kept.size();
  for (int i = 0; i < modes; ++i) {
    const auto begin = kept.begin() + static_cast<std::ptrdiff_t>(n * static_cast<std::size_t>(i) /
                                                                  static_cast<std::size_t>(modes));
    const auto end = kept.begin() + static_cast<std::ptrdiff_t>(
                                        n * static_cast<std::size_t>(i + 1) /
                                        static_cast<std::size_t>(modes));
    const double count = static_cast<double>(end - begin);
    const double mean = std::accumulate(begin, end, 0.0) / count;
    double spread = 0.0;
    for (auto it = begin; it != end; ++it) spread += (*it - mean) * (*it - mean);
    m.mean[i] = mean;
    m.variance[i] = std::max(spread / count, floor);
  }
  return m;
}

// The residual of the fitted spec on `rows` with every mode's shift taken out of nothing: y − X θ.
Eigen::VectorXd shared_residual(const ModelSpec& spec, const core::ExtendedParameters& fitted,
                                const SearchData& data, const std::vector<Eigen::Index>& rows) {
  const core::ExtendedDesign design = design_of(spec, data, fitted.model.modes.modes(), rows);
  return data.y()(rows) - design.shared * fitted.theta;
}

// One more mode, split from mode s: its halves kSplitHalfDistance σ either side, narrower, each
// with half the weight; the new one goes last so that the terms' mode indices stay valid.
void split_mode_into_two(core::ExtendedParameters& p, int s) {
  core::ExtendedMixture& m = p.model;
  const int modes = m.modes.modes();
  const double sigma = std::sqrt(m.modes.variance[s]);
  const auto grow = [](Eigen::VectorXd& v, double value) {
    v.conservativeResize(v.size() + 1);
    v[v.size() - 1] = value;
  };
  grow(m.modes.mean, m.modes.mean[s] + kSplitHalfDistance * sigma);
  m.modes.mean[s] -= kSplitHalfDistance * sigma;
  grow(m.modes.variance, kSplitVarianceShare * m.modes.variance[s]);
  m.modes.variance[s] *= kSplitVarianceShare;
  grow(m.modes.weight, 0.5 * m.modes.weight[s]);
  m.modes.weight[s] *= 0.5;
  if (m.weight_bins) {
    Eigen::MatrixXd& t = m.weight_bins->table;
    t.conservativeResize(Eigen::NoChange, modes + 1);
    t.col(modes) = 0.5 * t.col(s);
    t.col(s) *= 0.5;
    if (m.weight_bins->term.is_parametric_noise()) {
      // Half the weight each: both halves' log-odds fall by log 2 (mode 1's stay the reference).
      core::NoiseBins& b = m.weight_bins.value();
      grow(b.intercept, b.intercept[s]);
      grow(b.slope, b.slope[s]);
      if (s == 0) {
        b.intercept.tail(modes) .array() += std::log(2.0);
        b.intercept[0] = 0.0, b.intercept[modes] = 0.0;
      } else {
        b.intercept[s] -= std::log(2.0), b.intercept[modes] -= std::log(2.0);
      }
      b.refresh_table();
    }
  }
  if (m.variance_bins) {
    Eigen::MatrixXd& t = m.variance_bins->table;
    t.conservativeResize(Eigen::NoChange, modes + 1);
    t.col(s) *= kSplitVarianceShare;
    t.col(modes) = t.col(s);
    if (m.variance_bins->term.is_parametric_noise()) {
      core::NoiseBins& b = m.variance_bins.value();
      b.intercept[s] += std::log(kSplitVarianceShare);
      grow(b.intercept, b.intercept[s]);
      grow(b.slope, b.slope[s]);
      b.refresh_table();
    }
  }
  if (m.transition.size() > 0) {
    m.transition = kChainStartStay * Eigen::MatrixXd::Identity(modes + 1, modes + 1) +
                   (1.0 - kChainStartStay) * Eigen::VectorXd::Ones(modes + 1) *
                       m.modes.weight.transpose();
  }
  p.mode_coefficients.emplace_back(0);
}

// A noise term at the held model's values in every bin or level: the weights' log-odds against
// mode 1 (or the log-variances) as intercepts, no slope.
core::NoiseBins neutral_bins(const core::Term& term, const Eigen::VectorXd& values, bool weights) {
  core::NoiseBins bins{term, Eigen::VectorXd::Ones(term.levels()) * values.transpose(), {}, {}};
  if (term.is_parametric_noise()) {
    bins.intercept = weights ? Eigen::VectorXd((values.array() / values[0]).log())
                             : Eigen::VectorXd(values.array().log());
    bins.slope = Eigen::VectorXd::Zero(values.size());
    bins.refresh_table();
  }
  return bins;
}

}  // namespace

SearchData::SearchData(Eigen::VectorXd y_minus_d, const Eigen::MatrixXd& basis_design,
                       core::CovariateTable covariates,
                       const Eigen::VectorXd& held_theta,
                       const std::vector<Eigen::Index>& half_rows, double minimum_half_ranges)
    : y_(std::move(y_minus_d)), covariates_(std::move(covariates)) {
  if (basis_design.rows() != y_.size() || covariates_.size() != y_.size()) {
    throw core::InvalidInput("the search's ranges, basis design and covariates differ in length");
  }
  const Eigen::Index k = basis_design.rows();
  if (k < basis_design.cols() + 1) throw core::InvalidInput("fewer ranges than basis columns");
  column_mean_ = basis_design.colwise().mean();
  basis_centred_ = basis_design.rowwise() - column_mean_;
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(basis_centred_);
  qr.setThreshold(kRetainedDirection);
  const Eigen::Index rank = qr.rank();
  const double scale = std::sqrt(static_cast<double>(k));
  basis_design_ = (qr.householderQ() * Eigen::MatrixXd::Identity(k, rank)) * scale;
  r_ = qr.matrixQR().topLeftCorner(rank, rank).triangularView<Eigen::Upper>();
  r_ /= scale;
  for (Eigen::Index i = 0; i < rank; ++i) retained_.push_back(qr.colsPermutation().indices()[i]);
  rotation_ = Eigen::MatrixXd::Identity(rank, rank);
  // Each direction's share on the first half: the eigenvalues of G / K, G its Gram there. A
  // direction's weight on a half, in ranges (each range carries one on average), is its share
  // times K.
  const Eigen::MatrixXd half = basis_design_(half_rows, Eigen::all);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> shares(
      half.transpose() * half / static_cast<double>(k));
  const Eigen::ArrayXd share = shares.eigenvalues().array();
  const auto determined =
      (share.min(1.0 - share) * static_cast<double>(k) >= minimum_half_ranges).eval();
  undetermined_by_a_half_ = rank - determined.count();
  held_coordinates_ = Eigen::VectorXd::Zero(rank);
  if (undetermined_by_a_half_ == 0) return;
  if (held_theta.size() != basis_design.cols()) {
    throw core::InvalidInput("the search's held θ and basis design differ in columns");
  }
  // The undetermined directions' coordinates of the training's bias, held: subtracted from y.
  const Eigen::VectorXd coordinates = coordinates_of(held_theta);
  rotation_.resize(rank, rank - undetermined_by_a_half_);
  for (Eigen::Index i = 0, kept = 0; i < rank; ++i) {
    const Eigen::VectorXd direction = shares.eigenvectors().col(i);
    if (determined[i]) {
      rotation_.col(kept++) = direction;
    } else {
      held_coordinates_ += direction * direction.dot(coordinates);
    }
  }
  y_ -= basis_design_ * held_coordinates_;
  basis_design_ = basis_design_ * rotation_;
}

void SearchData::to_orthogonal(const Eigen::VectorXd& basis_theta, Eigen::VectorXd& theta,
                               Eigen::VectorXd& mean) const {
  theta = coordinates_of(basis_theta);
  // The bias's constant h̄θ joins the offsets.
  mean.array() += column_mean_.dot(basis_theta);
}

Eigen::VectorXd SearchData::coordinates_of(const Eigen::VectorXd& basis_theta) const {
  // The least-squares coordinates in Q of the centred bias (H − 1h̄)θ (QᵀQ = K I).
  return basis_design_.transpose() * (basis_centred_ * basis_theta) /
         static_cast<double>(y_.size());
}

void SearchData::to_basis(const Eigen::VectorXd& orthogonal_theta, Eigen::VectorXd& theta,
                          Eigen::VectorXd& mean) const {
  const Eigen::VectorXd retained =
      r_.triangularView<Eigen::Upper>().solve(rotation_ * orthogonal_theta + held_coordinates_);
  theta = Eigen::VectorXd::Zero(column_mean_.size());
  for (std::size_t i = 0; i < retained_.size(); ++i) {
    theta[retained_[i]] = retained[static_cast<Eigen::Index>(i)];
  }
  mean.array() -= column_mean_.dot(theta);
}

bool ModelSpec::accepts(const core::Term& term) const {
  if (term.parameter != core::Parameter::ExtraMode &&
      std::find(effects.begin(), effects.end(), term.label()) != effects.end()) {
    return false;
  }
  switch (term.parameter) {
    case core::Parameter::Weights:
      return !weight_term && !chain;
    case core::Parameter::Spread:
      return !variance_term;
    case core::Parameter::Markov:
      return !chain && !weight_term && !outliers;
    case core::Parameter::Outliers:
      return !outliers && !chain;
    case core::Parameter::ExtraMode:
      return extra_modes < kMaxExtraModes;
    case core::Parameter::Bias:
    case core::Parameter::ModeOffset:
      return true;
  }
  return false;
}

std::vector<Eigen::Index> all_rows_if_empty(const std::vector<Eigen::Index>& rows, Eigen::Index n) {
  if (!rows.empty()) return rows;
  std::vector<Eigen::Index> all(static_cast<std::size_t>(n));
  std::iota(all.begin(), all.end(), Eigen::Index{0});
  return all;
}

core::ExtendedDesign design_of(const ModelSpec& spec, const SearchData& data, int modes,
                               const std::vector<Eigen::Index>& rows_in) {
  const std::vector<Eigen::Index> rows = all_rows_if_empty(rows_in, data.size());
  const auto n = static_cast<Eigen::Index>(rows.size());
  core::ExtendedDesign design;
  Eigen::Index columns = data.basis_design().cols();
  for (const core::Term& t : spec.bias_terms) columns += t.columns();
  design.shared.resize(n, columns);
  design.shared.leftCols(data.basis_design().cols()) = data.basis_design()(rows, Eigen::all);
  Eigen::Index at = data.basis_design().cols();
  for (const core::Term& t : spec.bias_terms) {
    design.shared.middleCols(at, t.columns()) = data.columns(t)(rows, Eigen::all);
    at += t.columns();
  }
  design.mode_columns.assign(static_cast<std::size_t>(modes), Eigen::MatrixXd(0, 0));
  for (const core::Term& t : spec.offset_terms) {
    if (t.mode >= modes) throw core::InvalidInput("term " + t.describe() + " names no mode");
    auto& block = design.mode_columns[static_cast<std::size_t>(t.mode)];
    block = append_columns(block, data.columns(t)(rows, Eigen::all));
  }
  const int variance_states = spec.variance_term ? static_cast<int>(spec.variance_term->knots.size()) + 1 : 1;
  design.state = Eigen::VectorXi::Zero(n);
  if (spec.weight_term) design.state = data.bins(*spec.weight_term)(rows) * variance_states;
  if (spec.variance_term) design.state += data.bins(*spec.variance_term)(rows);
  return design;
}

Extended with_term(const ModelSpec& spec, const core::ExtendedParameters& fitted,
                   const core::Term& term, const SearchData& data,
                   const std::vector<Eigen::Index>& rows_in, int split_mode) {
  const std::vector<Eigen::Index> rows = all_rows_if_empty(rows_in, data.size());
  Extended out{spec, fitted};
  out.spec.effects.push_back(term.label());
  core::ExtendedMixture& m = out.start.model;
  const int modes = m.modes.modes();
  switch (term.parameter) {
    case core::Parameter::Bias:
      out.spec.bias_terms.push_back(term);
      out.start.theta = append_zeros(out.start.theta, term.columns());
      break;
    case core::Parameter::ModeOffset: {
      out.spec.offset_terms.push_back(term);
      Eigen::VectorXd& beta = out.start.mode_coefficients[static_cast<std::size_t>(term.mode)];
      beta = append_zeros(beta, term.columns());
      break;
    }
    case core::Parameter::Weights:
      out.spec.weight_term = term;
      m.weight_bins = neutral_bins(term, m.modes.weight, true);
      break;
    case core::Parameter::Spread:
      out.spec.variance_term = term;
      m.variance_bins = neutral_bins(term, m.modes.variance, false);
      break;
    case core::Parameter::Markov:
      out.spec.chain = true;
      m.transition = kChainStartStay * Eigen::MatrixXd::Identity(modes, modes) +
                     (1.0 - kChainStartStay) * Eigen::VectorXd::Ones(modes) *
                         m.modes.weight.transpose();
      break;
    case core::Parameter::Outliers: {
      out.spec.outliers = true;
      const Eigen::VectorXd residual = shared_residual(spec, fitted, data, rows);
      m.outlier_weight = kOutlierStartWeight;
      m.outlier_density = 1.0 / std::max(residual.maxCoeff() - residual.minCoeff(), 1.0);
      if (split_mode == 1) {
        // The modes of the trimmed residuals (their offsets without any mode shift).
        const core::MixtureParameters trimmed =
            trimmed_quantile_modes(residual, modes, m.modes.variance.minCoeff());
        m.modes.mean = trimmed.mean;
        m.modes.variance = trimmed.variance;
        if (m.variance_bins) m.variance_bins = neutral_bins(m.variance_bins->term, trimmed.variance, false);
      }
      break;
    }
    case core::Parameter::ExtraMode:
      out.spec.extra_modes += 1;
      split_mode_into_two(out.start, std::clamp(split_mode, 0, modes - 1));
      break;
  }
  return out;
}

core::Calibration calibration_of(const ModelSpec& spec, const core::ExtendedParameters& fitted,
                                 const core::Calibration& base, const SearchData& data) {
  core::Calibration c = base;
  const Eigen::Index p = data.basis_design().cols();
  core::ExtendedParameters back = fitted;
  data.to_basis(fitted.theta.head(p), c.model.theta, back.model.modes.mean);
  c.model.mixture = back.model.modes;
  if (spec.effects.empty()) {
    c.extension.reset();
    return c;
  }
  core::ModelExtension e;
  e.effects = spec.effects;
  Eigen::Index at = p;
  for (const core::Term& t : spec.bias_terms) {
    e.mean_terms.push_back({t, fitted.theta.segment(at, t.columns())});
    at += t.columns();
  }
  std::vector<Eigen::Index> mode_at(fitted.mode_coefficients.size(), 0);
  for (const core::Term& t : spec.offset_terms) {
    const auto i = static_cast<std::size_t>(t.mode);
    e.mean_terms.push_back({t, fitted.mode_coefficients[i].segment(mode_at[i], t.columns())});
    mode_at[i] += t.columns();
  }
  e.extended_mixture = back.model;
  e.validate();
  c.extension = std::move(e);
  return c;
}

int added_parameters(const ModelSpec& spec, int modes) {
  int n = 0;
  for (const core::Term& t : spec.bias_terms) n += t.columns();
  for (const core::Term& t : spec.offset_terms) n += t.columns();
  const auto noise = [](const core::Term& t, int free_modes) {
    return t.is_parametric_noise() ? free_modes : static_cast<int>(t.knots.size()) * free_modes;
  };
  if (spec.weight_term) n += noise(*spec.weight_term, modes - 1);
  if (spec.variance_term) n += noise(*spec.variance_term, modes);
  if (spec.chain) n += modes * (modes - 1);
  if (spec.outliers) n += 1;
  n += 3 * spec.extra_modes;
  return n;
}

}  // namespace tofcomp::calibration
