// Bounds checks on an option's text before CLI11 converts it (cli/number_checks.hpp).
#include "cli/number_checks.hpp"

#include <fmt/format.h>

#include <functional>
#include <string>

#include "core/error.hpp"

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

CLI::Validator parsed_by(std::function<void(const std::string&)> parse, std::string option_prefix,
                         std::string value_name) {
  return CLI::Validator(
      [parse = std::move(parse), prefix = std::move(option_prefix)](const std::string& text) {
        try {
          parse(text);
          return std::string();
        } catch (const core::InvalidInput& e) {
          const std::string message = e.what();
          return message.rfind(prefix, 0) == 0 ? message.substr(prefix.size()) : message;
        }
      },
      std::move(value_name));
}

}  // namespace tofcomp::cli
