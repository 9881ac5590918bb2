#include "core/validation.hpp"

#include <cmath>
#include <sstream>

#include "core/error.hpp"

namespace tofcomp::core {

void require_finite(const Eigen::Ref<const Eigen::MatrixXd>& values, std::string_view name) {
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
