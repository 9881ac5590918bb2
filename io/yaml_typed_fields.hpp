// Typed, range-checked reading of one key of a strict YAML file (tofcompd.yaml, the MQTT
// bridge's configuration) on top of io::YamlMap: numbers and whole numbers within a range, one of
// a set of names or values, paths resolved against the configuration's directory, octal file
// modes, optional sections. Every failure is an io::YamlSchemaError naming the key path and what
// was expected ("outputs.shm.slots must be at least 2, not 1").
#pragma once

#include <chrono>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "io/yaml_fields.hpp"

namespace tofcomp::io::fields {

// An interval of the real line; either end open or closed, or unbounded.
struct Range {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_exclusive = false;
  bool max_exclusive = false;

  bool contains(double value) const;
  // "at least 2", "greater than 0 and at most 3600", "between 0 and 1".
  std::string describe() const;
};
Range at_least(double min);
Range greater_than(double min);
Range between(double min, double max);  // both ends included
Range greater_than_up_to(double min_excluded, double max);

// A number as messages show it: whole numbers without a decimal point, others with up to ten
// significant digits.
std::string format_number(double value);

// Numbers (finite) within `range`.
double required_number(const io::YamlMap& map, std::string_view key, const Range& range);
double number(const io::YamlMap& map, std::string_view key, const Range& range, double fallback);
std::optional<double> optional_number(const io::YamlMap& map, std::string_view key,
                                      const Range& range);

// A whole number (decimal, or hexadecimal as 0x48). yaml-cpp reads one written with a leading 0
// as octal ("0100" is 64): refused, so that what is written is what is meant.
bool reads_as_octal(std::string_view scalar);
long whole_number(const io::YamlMap& map, std::string_view key);

// Whole numbers within `range`.
long required_integer(const io::YamlMap& map, std::string_view key, const Range& range);
long integer(const io::YamlMap& map, std::string_view key, const Range& range, long fallback);
std::optional<long> optional_integer(const io::YamlMap& map, std::string_view key,
                                     const Range& range);

// Milliseconds as a whole number within `range`.
std::chrono::milliseconds milliseconds(const io::YamlMap& map, std::string_view key,
                                       const Range& range, std::chrono::milliseconds fallback);

// A whole number or a number that must be one of `allowed`.
long integer_choice(const io::YamlMap& map, std::string_view key,
                    std::initializer_list<long> allowed, long fallback);
double number_choice(const io::YamlMap& map, std::string_view key,
                     std::initializer_list<double> allowed, double fallback);

// One of a set of names.
template <class T>
struct Named {
  std::string_view name;
  T value;
};

[[noreturn]] void fail_choice(const io::YamlMap& map, std::string_view key, std::string_view got,
                              const std::vector<std::string_view>& names);

template <class T>
T choice(const io::YamlMap& map, std::string_view key, std::initializer_list<Named<T>> choices,
         std::optional<T> fallback) {
  if (!map.has(key) && fallback) return *fallback;
  const std::string got = map.text(key);  // a missing required key fails here
  std::vector<std::string_view> names;
  for (const auto& c : choices) {
    if (c.name == got) return c.value;
    names.push_back(c.name);
  }
  fail_choice(map, key, got, names);
}

// Non-empty text.
std::string required_text(const io::YamlMap& map, std::string_view key);
std::string text(const io::YamlMap& map, std::string_view key, std::string fallback);

// A path, made absolute against `base` when relative and normalized. Empty text is an error.
std::filesystem::path resolve_path(const std::filesystem::path& path,
                                   const std::filesystem::path& base);
std::filesystem::path required_path(const io::YamlMap& map, std::string_view key,
                                    const std::filesystem::path& base);
std::filesystem::path path(const io::YamlMap& map, std::string_view key,
                           const std::filesystem::path& base, std::filesystem::path fallback);

// A file mode of three octal digits, optionally after a 0: "0660", "640". Quoting is advised
// (an unquoted 0660 is read as text all the same).
unsigned octal_mode(const io::YamlMap& map, std::string_view key, unsigned fallback);
// "0660"
std::string format_octal_mode(unsigned mode);

// The mapping at `key`, checked against `allowed`; nullopt when the key is absent or empty
// (`recording:` with every entry commented out).
std::optional<io::YamlMap> section(const io::YamlMap& parent, std::string_view key,
                                   std::initializer_list<std::string_view> allowed);

}  // namespace tofcomp::io::fields
