#include "core/measurement_model.hpp"

#include <sstream>

#include "core/error.hpp"
#include "core/validation.hpp"

namespace tofcomp::core {

void MeasurementModel::validate() const {
  if (theta.size() != basis.columns()) {
    std::ostringstream msg;
    msg << "θ has " << theta.size() << " coefficients but the basis " << basis.describe() << " has "
        << basis.columns() << " columns";
    throw InvalidInput(msg.str());
  }
  require_finite(theta, "theta");
  noise.validate();
}

Eigen::VectorXd MeasurementModel::bias(
    const Eigen::Ref<const Eigen::VectorXd>& junction_temperature_c) const {
  return basis.design_matrix(junction_temperature_c) * theta;
}

double MeasurementModel::bias_at(double junction_temperature_c) const {
  Eigen::RowVectorXd row(basis.columns());
  basis.row(junction_temperature_c, row);
  return row.dot(theta);
}

}  // namespace tofcomp::core
