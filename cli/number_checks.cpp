// Bounds checks on an option's text before CLI11 converts it (cli/number_checks.hpp).
#include "cli/number_checks.hpp"

#include <fmt/format.h>

#include <functional>
#include <string>

namespace tofcomp::cli {

namespace {

// A validator that reads the option's text as a number and asks `accepts`; `requirement` is what
// its refusal says ("must be at least 1"), `shown` what --help shows beside the option.
CLI::Validator number_check(std::function<bool(double)> accepts, const std::string& requirement,
                            const std::string& shown) {
  return CLI::Validator(
      [accepts = std::move(accepts), requirement](std::string& text) -> std::string {
        double value = 0.0;
        if (!CLI::detail::lexical_cast(text, value)) return "'" + text + "' is not a number";
        if (!accepts(value)) return requirement + ", not " + text;
        return {};
      },
      shown);
}

}  // namespace

CLI::Validator at_least(double minimum) {
  return number_check([minimum](double v) { return v >= minimum; },
                      fmt::format("must be at least {}", minimum), fmt::format(">= {}", minimum));
}

CLI::Validator greater_than(double bound) {
  return number_check([bound](double v) { return v > bound; },
                      fmt::format("must be greater than {}", bound), fmt::format("> {}", bound));
}

CLI::Validator between(double lowest, double highest) {
  return number_check([lowest, highest](double v) { return v >= lowest && v <= highest; },
                      fmt::format("must be between {} and {}", lowest, highest),
                      fmt::format("{} to {}", lowest, highest));
}

}  // namespace tofcomp::cli
