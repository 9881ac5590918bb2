// §4: the temperature bases H(.) of the measurement model y = d + H(t^j) θ + noise (Eq. 8).
//
// A Basis maps junction temperatures t^j to the rows H(t^j) of the design matrix H (Eq. 17).
// It is a list of terms, concatenated column-wise (a "composed" basis):
//   - Polynomial of order N, N columns (Eq. 9). Two forms span the same model once the mode
//     offsets μ_i (which carry the constant) are added:
//       RawPower  [t, t^2, ..., t^N]               the paper's form, for reproduction only:
//                                                  at t ≈ 25 °C its columns differ by 25^16 ≈ 1e22
//       Legendre  [P_1(z), ..., P_N(z)],  z = (t − center) / half_range   (default)
//                 orthogonal on z ∈ [−1, 1], so order 16 on the training range is well conditioned.
//   - Fourier of order N, 2N columns (Eq. 11): [cos(2π n f0 t), sin(2π n f0 t)], n = 1..N,
//     f0 in 1/°C, on the raw temperature exactly as printed.
// Cost: O(K·p) time and memory for K temperatures and p columns.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace tofcomp::core {

enum class BasisKind { Polynomial, Fourier };
enum class PolynomialForm { Legendre, RawPower };

struct BasisTerm {
  BasisKind kind = BasisKind::Polynomial;
  int order = 1;                                   // N of Eq. 9 or Eq. 11
  PolynomialForm form = PolynomialForm::Legendre;  // polynomial terms only
  double f0_per_c = 0.0;                           // Fourier terms only: fundamental, 1/°C

  int columns() const { return kind == BasisKind::Polynomial ? order : 2 * order; }
};

// The narrowest half range a scaling is given: a range of temperatures narrower than 1e-3 °C is
// widened to it, so that a constant temperature does not divide by zero.
inline constexpr double kMinScalingHalfRangeC = 5e-4;

// The affine map z = (t − center_c) / half_range_c that puts the training temperatures on
// [−1, 1] for the Legendre form.
struct TemperatureScaling {
  double center_c = 0.0;
  double half_range_c = 1.0;

  // The scaling that maps [min(t), max(t)] onto [−1, 1]; a range narrower than 1e-3 °C is
  // widened to it so that a constant temperature does not divide by zero.
  static TemperatureScaling spanning(const Eigen::Ref<const Eigen::VectorXd>& temperatures_c);
};

class Basis {
 public:
  Basis() = default;
  Basis(std::vector<BasisTerm> terms, TemperatureScaling scaling);

  // Eq. 9 with the default well-conditioned form, scaled to the given temperatures.
  static Basis polynomial(int order, const Eigen::Ref<const Eigen::VectorXd>& temperatures_c,
                          PolynomialForm form = PolynomialForm::Legendre);
  // Eq. 11.
  static Basis fourier(int order, double f0_per_c);

  const std::vector<BasisTerm>& terms() const { return terms_; }
  const TemperatureScaling& scaling() const { return scaling_; }
  int columns() const { return columns_; }
  // A short name such as "polynomial(16, legendre)" or "polynomial(4)+fourier(2, f0=0.1)".
  std::string describe() const;

  // H of Eq. 17: one row H(t_k) per temperature (K × p). Throws InvalidInput on a non-finite
  // temperature.
  Eigen::MatrixXd design_matrix(const Eigen::Ref<const Eigen::VectorXd>& temperatures_c) const;
  // One row H(t) (1 × p), for the real-time path.
  void row(double temperature_c, Eigen::Ref<Eigen::RowVectorXd> out) const;

 private:
  std::vector<BasisTerm> terms_;
  TemperatureScaling scaling_;
  int columns_ = 0;
};

}  // namespace tofcomp::core
