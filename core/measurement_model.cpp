#include "core/measurement_model.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/error.hpp"
#include "core/validation.hpp"

namespace tofcomp::core {

namespace {

// The tangent's slope at an end of the trained range: a difference over this share of the range
// (at least kMinimumTangentStepC), inside it.
constexpr double kTangentStepFraction = 0.01;
constexpr double kMinimumTangentStepC = 1e-3;

}  // namespace

void MeasurementModel::validate() const {
  if (theta.size() != basis.columns()) {
    std::ostringstream msg;
    msg << "θ has " << theta.size() << " coefficients but the basis " << basis.describe() << " has "
        << basis.columns() << " columns";
    throw InvalidInput(msg.str());
  }
  require_finite(theta, "theta");
  mixture.validate();
  if (trained_junction_c &&
      !(std::isfinite(trained_junction_c->min_c) && std::isfinite(trained_junction_c->max_c) &&
        trained_junction_c->min_c <= trained_junction_c->max_c)) {
    throw InvalidInput("the trained junction range must be finite with min <= max");
  }
}

double TemperatureRange::clamp(double t_c) const {
  return std::clamp(t_c, min_c, max_c);
}

bool MeasurementModel::extrapolates(double junction_temperature_c) const {
  return trained_junction_c && !trained_junction_c->contains(junction_temperature_c);
}

Eigen::VectorXd MeasurementModel::bias(
    const Eigen::Ref<const Eigen::VectorXd>& junction_temperature_c) const {
  Eigen::VectorXd out = basis.design_matrix(junction_temperature_c) * theta;
  if (!trained_junction_c) return out;
  for (Eigen::Index k = 0; k < out.size(); ++k) {
    if (extrapolates(junction_temperature_c[k])) out[k] = bias_at(junction_temperature_c[k]);
  }
  return out;
}

double MeasurementModel::basis_bias_at(double junction_temperature_c) const {
  Eigen::RowVectorXd row(basis.columns());
  basis.row(junction_temperature_c, row);
  return row.dot(theta);
}

double MeasurementModel::bias_at(double junction_temperature_c) const {
  if (!extrapolates(junction_temperature_c)) return basis_bias_at(junction_temperature_c);
  // The tangent at the nearer end, its slope by a one-sided difference over a small inner step.
  const TemperatureRange& range = *trained_junction_c;
  const double edge = range.clamp(junction_temperature_c);
  const double step =
      std::max(kTangentStepFraction * (range.max_c - range.min_c), kMinimumTangentStepC);
  const double inner = edge == range.max_c ? edge - step : edge + step;
  const double at_edge = basis_bias_at(edge);
  const double slope = (at_edge - basis_bias_at(inner)) / (edge - inner);
  return at_edge + slope * (junction_temperature_c - edge);
}

}  // namespace tofcomp::core
