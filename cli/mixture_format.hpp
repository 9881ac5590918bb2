// The lasing modes of Eq. 8's mixture in the command line's text and JSON: one line or object a
// mode (offset, standard deviation, weight), for every command that prints a mixture.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "core/gaussian_mixture.hpp"

namespace tofcomp::cli {

// [{offset_mm, std_mm, weight}, ...]
nlohmann::json modes_json(const core::MixtureParameters& modes);
// "  mode 1: offset -2.000 mm, std 0.900 mm, weight 0.550\n", one line a mode.
std::string modes_text(const core::MixtureParameters& modes);

}  // namespace tofcomp::cli
