#include "core/basis.hpp"

#include <cmath>
#include <numbers>
#include <sstream>
#include <utility>

#include "core/error.hpp"
#include "core/validation.hpp"

namespace tofcomp::core {
namespace {

constexpr int kMaxOrder = 1000;

void validate_term(const BasisTerm& term) {
  if (term.order < 1 || term.order > kMaxOrder) {
    std::ostringstream msg;
    msg << "basis order " << term.order << " is out of range: it must be 1.." << kMaxOrder;
    throw InvalidInput(msg.str());
  }
  if (term.kind == BasisKind::Fourier) {
    require_positive(term.f0_per_c, "Fourier fundamental f0 (1/°C)");
  }
}

// The three-term recurrence (n+1) P_{n+1} = (2n+1) z P_n − n P_{n−1}, at one z (double) or at
// a column of them (Eigen::ArrayXd): the same operations in the same order either way, so a
// design matrix built a column at a time holds its rows' values.
template <typename Value>
Value legendre_next(int n, const Value& z, const Value& current, const Value& previous) {
  return ((2.0 * n + 1.0) * z * current - n * previous) / (n + 1.0);
}

// Legendre P_1..P_N at z.
void legendre_columns(double z, int order, double* out) {
  double previous = 1.0;  // P_0
  double current = z;     // P_1
  out[0] = current;
  for (int n = 1; n < order; ++n) {
    const double next = legendre_next(n, z, current, previous);
    previous = current;
    current = next;
    out[n] = current;
  }
}

// Eq. 9 as printed: t, t^2, ..., t^N.
void raw_power_columns(double t, int order, double* out) {
  double power = t;
  for (int n = 0; n < order; ++n) {
    out[n] = power;
    power *= t;
  }
}

// Eq. 11: cos(2π n f0 t), sin(2π n f0 t) for n = 1..N, by angle addition from the fundamental.
void fourier_columns(double t, int order, double f0, double* out) {
  const double angle = 2.0 * std::numbers::pi * f0 * t;
  const double c1 = std::cos(angle);
  const double s1 = std::sin(angle);
  double c = c1;
  double s = s1;
  for (int n = 0; n < order; ++n) {
    if (n % 16 == 15) {  // re-anchor the recurrence so rounding does not accumulate
      c = std::cos((n + 1) * angle);
      s = std::sin((n + 1) * angle);
    }
    double* pair = out + 2 * static_cast<std::ptrdiff_t>(n);
    pair[0] = c;
    pair[1] = s;
    const double next_c = c * c1 - s * s1;
    const double next_s = s * c1 + c * s1;
    c = next_c;
    s = next_s;
  }
}

const char* form_name(PolynomialForm form) {
  return form == PolynomialForm::Legendre ? "legendre" : "raw";
}

}  // namespace

TemperatureScaling TemperatureScaling::spanning(
    const Eigen::Ref<const Eigen::VectorXd>& temperatures_c) {
  if (temperatures_c.size() == 0) {
    throw InvalidInput("cannot scale a basis to an empty set of temperatures");
  }
  require_finite(temperatures_c, "temperature");
  const double lo = temperatures_c.minCoeff();
  const double hi = temperatures_c.maxCoeff();
  return TemperatureScaling{0.5 * (lo + hi), std::max(0.5 * (hi - lo), kMinScalingHalfRangeC)};
}

Basis::Basis(std::vector<BasisTerm> terms, TemperatureScaling scaling)
    : terms_(std::move(terms)), scaling_(scaling) {
  if (terms_.empty()) {
    throw InvalidInput("a basis needs at least one term");
  }
  require_finite(scaling_.center_c, "basis scaling center");
  require_positive(scaling_.half_range_c, "basis scaling half range");
  for (const auto& term : terms_) {
    validate_term(term);
    columns_ += term.columns();
  }
}

Basis Basis::polynomial(int order, const Eigen::Ref<const Eigen::VectorXd>& temperatures_c,
                        PolynomialForm form) {
  BasisTerm term{BasisKind::Polynomial, order, form, 0.0};
  return Basis({term}, TemperatureScaling::spanning(temperatures_c));
}

Basis Basis::fourier(int order, double f0_per_c) {
  BasisTerm term{BasisKind::Fourier, order, PolynomialForm::Legendre, f0_per_c};
  return Basis({term}, TemperatureScaling{});
}

std::string Basis::describe() const {
  std::ostringstream out;
  for (std::size_t i = 0; i < terms_.size(); ++i) {
    const auto& term = terms_[i];
    if (i > 0) out << "+";
    if (term.kind == BasisKind::Polynomial) {
      out << "polynomial(" << term.order << ", " << form_name(term.form) << ")";
    } else {
      out << "fourier(" << term.order << ", f0=" << term.f0_per_c << ")";
    }
  }
  return out.str();
}

void Basis::row(double temperature_c, Eigen::Ref<Eigen::RowVectorXd> out) const {
  require_finite(temperature_c, "junction temperature");
  if (out.size() != columns_) {
    throw InvalidInput("basis row buffer has the wrong number of columns");
  }
  int offset = 0;
  for (const auto& term : terms_) {
    double* dst = out.data() + offset;
    if (term.kind == BasisKind::Fourier) {
      fourier_columns(temperature_c, term.order, term.f0_per_c, dst);
    } else if (term.form == PolynomialForm::RawPower) {
      raw_power_columns(temperature_c, term.order, dst);
    } else {
      const double z = (temperature_c - scaling_.center_c) / scaling_.half_range_c;
      legendre_columns(z, term.order, dst);
    }
    offset += term.columns();
  }
}

Eigen::MatrixXd Basis::design_matrix(
    const Eigen::Ref<const Eigen::VectorXd>& temperatures_c) const {
  if (columns_ == 0) {
    throw InvalidInput("the basis has no columns");
  }
  require_finite(temperatures_c, "junction temperature");
  // Column by column, each column one vectorized pass over the K temperatures with the same
  // arithmetic as row() (the same operations in the same order, so the same values): the design
  // is built for every point of the junction's search and every structure candidate, and a row at
  // a time wrote the column-major matrix with a stride of K.
  const Eigen::Index k = temperatures_c.size();
  Eigen::MatrixXd h(k, columns_);
  Eigen::Index offset = 0;
  for (const auto& term : terms_) {
    auto block = h.middleCols(offset, term.columns()).array();
    if (term.kind == BasisKind::Fourier) {
      Eigen::RowVectorXd scratch(term.columns());
      for (Eigen::Index r = 0; r < k; ++r) {
        fourier_columns(temperatures_c[r], term.order, term.f0_per_c, scratch.data());
        h.row(r).segment(offset, term.columns()) = scratch;
      }
    } else if (term.form == PolynomialForm::RawPower) {
      block.col(0) = temperatures_c.array();
      for (int n = 1; n < term.order; ++n) block.col(n) = block.col(n - 1) * temperatures_c.array();
    } else {
      // legendre_columns, a column at a time.
      const Eigen::ArrayXd z = (temperatures_c.array() - scaling_.center_c) / scaling_.half_range_c;
      Eigen::ArrayXd previous = Eigen::ArrayXd::Ones(k);  // P_0
      Eigen::ArrayXd current = z;                         // P_1
      block.col(0) = current;
      for (int n = 1; n < term.order; ++n) {
        Eigen::ArrayXd next = legendre_next(n, z, current, previous);
        previous = std::move(current);
        current = std::move(next);
        block.col(n) = current;
      }
    }
    offset += term.columns();
  }
  return h;
}

}  // namespace tofcomp::core
