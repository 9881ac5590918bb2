#include "core/validation.hpp"

#include <cmath>
#include <sstream>

#include "core/error.hpp"

namespace tofcomp::core {
namespace {

// Σ x · 0 over every value, a column at a time (a block of a larger matrix is not contiguous).
double columns_sum_of_zeroed(const Eigen::Ref<const Eigen::MatrixXd>& values) {
  double sum = 0.0;
  for (Eigen::Index c = 0; c < values.cols(); ++c) sum += (values.col(c).array() * 0.0).sum();
  return sum;
}

}  // namespace

void require_finite(const Eigen::Ref<const Eigen::MatrixXd>& values, std::string_view name) {
  // The common case in one vectorized pass: x · 0 is 0 for every finite x and NaN for ±∞ and NaN,
  // so the sum is 0 exactly when every value is finite (no overflow can reach it). Only otherwise is
  // the offending value looked for, element by element (the fits validate their K × p designs on
  // every call, and the element-wise loop, which cannot vectorize, took 2 % of `diagnose`).
  if (columns_sum_of_zeroed(values) == 0.0) return;
  for (Eigen::Index c = 0; c < values.cols(); ++c) {
    for (Eigen::Index r = 0; r < values.rows(); ++r) {
      if (!std::isfinite(values(r, c))) {
        std::ostringstream msg;
        msg << name;
        if (values.cols() == 1) {
          msg << "[" << r << "]";
        } else {
          msg << "(" << r << ", " << c << ")";
        }
        msg << " is " << values(r, c) << ": every value must be finite";
        throw InvalidInput(msg.str());
      }
    }
  }
}

void require_finite(double value, std::string_view name) {
  if (!std::isfinite(value)) {
    std::ostringstream msg;
    msg << name << " is " << value << ": it must be finite";
    throw InvalidInput(msg.str());
  }
}

void require_same_length(Eigen::Index a, std::string_view name_a, Eigen::Index b,
                         std::string_view name_b) {
  if (a != b) {
    std::ostringstream msg;
    msg << name_a << " has " << a << " entries but " << name_b << " has " << b
        << ": they must have the same length";
    throw InvalidInput(msg.str());
  }
}

void require_positive(double value, std::string_view name) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    std::ostringstream msg;
    msg << name << " is " << value << ": it must be a positive finite number";
    throw InvalidInput(msg.str());
  }
}

}  // namespace tofcomp::core
