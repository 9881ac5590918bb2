#include "io/covariates_csv.hpp"

#include <fmt/format.h>

#include <string>
#include <vector>

#include "core/effect_grammar.hpp"
#include "core/validation.hpp"

namespace tofcomp::io {
namespace {

// A covariate's unit (core::covariate_unit) as a column name's suffix, in ASCII: "°C" → "c",
// "°C/min" → "c_per_min".
std::string unit_suffix(core::Covariate c) {
  std::string unit = core::covariate_unit(c);
  const std::string degrees = "°C";
  if (const auto at = unit.find(degrees); at != std::string::npos) unit.replace(at, degrees.size(), "c");
  if (const auto at = unit.find('/'); at != std::string::npos) unit.replace(at, 1, "_per_");
  return unit;
}

struct Column {
  std::string name;
  Eigen::VectorXd values;
};

}  // namespace

void write_covariates_csv(std::ostream& out, const Eigen::Ref<const Eigen::VectorXd>& time_s,
                          const Eigen::Ref<const Eigen::VectorXd>& residual_mm,
                          const core::CovariateTable& covariates) {
  core::require_same_length(time_s.size(), "range times", covariates.size(), "covariate rows");
  core::require_same_length(residual_mm.size(), "residuals", covariates.size(), "covariate rows");
  std::vector<Column> columns{{"time_s", time_s}, {"residual_mm", residual_mm}};
  for (const core::Covariate c : core::kCovariates) {
    if (c == core::Covariate::JunctionLag || !covariates.available(c)) continue;
    columns.push_back({fmt::format("{}_{}", core::covariate_token(c), unit_suffix(c)),
                       covariates.values(c)});
  }
  for (const double tau : core::kTimeConstantGridS) {
    columns.push_back({fmt::format("{}_{:g}s_{}", core::covariate_token(core::Covariate::JunctionLag),
                                   tau, unit_suffix(core::Covariate::JunctionLag)),
                       covariates.values(core::Covariate::JunctionLag, tau)});
  }
  for (std::size_t c = 0; c < columns.size(); ++c) out << (c ? "," : "") << columns[c].name;
  out << '\n';
  for (Eigen::Index k = 0; k < covariates.size(); ++k) {
    for (std::size_t c = 0; c < columns.size(); ++c) {
      out << (c ? "," : "") << fmt::format("{:.10g}", columns[c].values[k]);
    }
    out << '\n';
  }
}

}  // namespace tofcomp::io
