// Bounds for numeric options whose refusals read as a person would say them ("--count: must be
// at least 1, not 0"), in place of CLI11's Range, which prints both bounds with six decimals
// (PositiveNumber's upper bound, the largest double, runs to some 300 digits).
#pragma once

#include <CLI/CLI.hpp>

namespace tofcomp::cli {

// minimum ≤ value.
CLI::Validator at_least(double minimum);
// value > bound (a positive number: greater_than(0)).
CLI::Validator greater_than(double bound);
// lowest ≤ value ≤ highest.
CLI::Validator between(double lowest, double highest);

}  // namespace tofcomp::cli
