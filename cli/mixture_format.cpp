#include "cli/mixture_format.hpp"

#include <fmt/format.h>

#include <cmath>

namespace tofcomp::cli {

nlohmann::json modes_json(const core::MixtureParameters& modes) {
  nlohmann::json out = nlohmann::json::array();
  for (int i = 0; i < modes.modes(); ++i) {
    out.push_back({{"offset_mm", modes.mean[i]},
                   {"std_mm", std::sqrt(modes.variance[i])},
                   {"weight", modes.weight[i]}});
  }
  return out;
}

std::string modes_text(const core::MixtureParameters& modes) {
  std::string out;
  for (int i = 0; i < modes.modes(); ++i) {
    out += fmt::format("  mode {}: offset {:+.3f} mm, std {:.3f} mm, weight {:.3f}\n", i + 1,
                       modes.mean[i], std::sqrt(modes.variance[i]), modes.weight[i]);
  }
  return out;
}

}  // namespace tofcomp::cli
