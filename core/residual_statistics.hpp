// The statistics of the residual tests (core/residual_diagnosis.hpp), computed alike on the
// data's residuals and on each draw of the trained model that calibrates them. What the tests
// read besides the residual (the temperature quartiles, the junction's ranks, the covariates the
// residual is correlated with) is fixed across the draws, so it is prepared once.
//
// A residual r_k = y_k − d − H_k θ̂ (the modes still in it) gets its most probable mode i
// (Eq. 18), its mode-compensated residual e_k = r_k − μ_i and its standardized z_k = e_k / σ_i;
//   runs                 the Wald–Wolfowitz z of the sequence "mode 1 or not" (negative: fewer
//                        runs than independent modes make)
//   weights χ²           Pearson's χ² of the table mode × junction-temperature quartile
//   spread ρ             Spearman's ρ of the junction temperature and |z|
//   heating, drift r     Pearson's r of e with the junction's heating rate, with the time
//   warm-up r            Pearson's r of e with exp(−t_on/τ), one per τ of core/warm_up.hpp
//   Ljung–Box Q          of e, lags 1..h
// Each comes as a TestResult against its textbook law (core/statistical_tests.hpp), which holds
// for independent continuous residuals; the diagnosis replaces the law by the draws' where the
// data are rounded (core/residual_diagnosis.hpp).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "core/gaussian_mixture.hpp"
#include "core/statistical_tests.hpp"

namespace tofcomp::core {

struct ResidualStatistics {
  std::optional<TestResult> runs;     // two modes or more, two ranges of each label
  std::optional<TestResult> weights;  // two modes or more
  TestResult spread;
  TestResult heating;
  TestResult drift;
  std::vector<TestResult> warm_up;  // one per τ of kWarmUpTimeConstantsS
  TestResult ljung_box;
};

// A residual's hard assignment: its most probable mode and e, z at each range.
struct ModeAssignment {
  Eigen::VectorXi mode;
  Eigen::VectorXd compensated;   // e_k
  Eigen::VectorXd standardized;  // z_k
};

// The most probable mode of each residual under the mixture (the argmax of Eq. 18's weights),
// with e and z.
ModeAssignment assign_modes(const Eigen::Ref<const Eigen::VectorXd>& residual,
                            const MixtureParameters& mixture);

class ResidualTestDesign {
 public:
  // The covariates at each range (time order), the mixture the residuals are read under, the
  // Ljung–Box lags. Throws InvalidInput on mismatched lengths or lags outside 1..n−1.
  ResidualTestDesign(const Eigen::Ref<const Eigen::VectorXd>& time_s,
                     const Eigen::Ref<const Eigen::VectorXd>& junction_c,
                     const Eigen::Ref<const Eigen::VectorXd>& junction_rate_c_per_s,
                     const Eigen::Ref<const Eigen::VectorXd>& time_since_power_on_s,
                     const MixtureParameters& mixture, int ljung_box_lags);

  Eigen::Index size() const { return junction_rank_.size(); }
  int ljung_box_lags() const { return lags_; }
  const MixtureParameters& mixture() const { return mixture_; }

  // The statistics of one residual vector; `assignment` (when given) receives its modes.
  ResidualStatistics statistics(const Eigen::Ref<const Eigen::VectorXd>& residual,
                                ModeAssignment* assignment = nullptr) const;

 private:
  MixtureParameters mixture_;
  int lags_ = 0;
  Eigen::VectorXi temperature_quartile_;
  Eigen::VectorXd junction_rank_;  // centred and scaled to unit norm
  // The correlates of e, each centred and scaled to unit norm: the heating rate, the time, then
  // one column per warm-up τ; a column with no spread is zero (its r is 0).
  Eigen::MatrixXd correlates_;
};

// Ranks 0..n−1 of the values to float precision (ties broken by position: residuals less a
// continuous prediction do not tie). At most 2³² values.
Eigen::VectorXd ranks(const Eigen::Ref<const Eigen::VectorXd>& v);

}  // namespace tofcomp::core
