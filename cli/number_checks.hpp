// Bounds for numeric options whose refusals read as a person would say them ("--count: must be
// at least 1, not 0"), in place of CLI11's Range, which prints both bounds with six decimals
// (PositiveNumber's upper bound, the largest double, runs to some 300 digits).
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>

namespace tofcomp::cli {

// minimum ≤ value.
CLI::Validator at_least(double minimum);
// value > bound (a positive number: greater_than(0)).
CLI::Validator greater_than(double bound);
// lowest ≤ value ≤ highest.
CLI::Validator between(double lowest, double highest);

// A value that `parse` takes (it throws core::InvalidInput otherwise, its message naming the
// option with `option_prefix` first, which CLI11 adds itself and is taken off); `value_name` is
// what the help calls the value (FIRST:LAST).
CLI::Validator parsed_by(std::function<void(const std::string&)> parse, std::string option_prefix,
                         std::string value_name);

}  // namespace tofcomp::cli
