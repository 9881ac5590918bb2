// Typed, range-checked reading of one key of a strict YAML file.
#include "io/yaml_typed_fields.hpp"

#include <cmath>
#include <cstdio>
#include <utility>

namespace tofcomp::io::fields {

bool Range::contains(double value) const {
  const bool above_min = min_exclusive ? value > min : value >= min;
  const bool below_max = max_exclusive ? value < max : value <= max;
  return above_min && below_max;
}

std::string Range::describe() const {
  const bool has_min = std::isfinite(min);
  const bool has_max = std::isfinite(max);
  if (has_min && has_max && !min_exclusive && !max_exclusive) {
    return "between " + format_number(min) + " and " + format_number(max);
  }
  std::string out;
  if (has_min) out = (min_exclusive ? "greater than " : "at least ") + format_number(min);
  if (has_max) {
    if (!out.empty()) out += " and ";
    out += (max_exclusive ? "less than " : "at most ") + format_number(max);
  }
  return out.empty() ? "a finite number" : out;
}

Range at_least(double min) {
  return Range{.min = min};
}
Range greater_than(double min) {
  return Range{.min = min, .min_exclusive = true};
}
Range between(double min, double max) {
  return Range{.min = min, .max = max};
}
Range greater_than_up_to(double min_excluded, double max) {
  return Range{.min = min_excluded, .max = max, .min_exclusive = true};
}

std::string format_number(double value) {
  char text[32];
  if (value == std::floor(value) && std::fabs(value) < 1e15) {
    std::snprintf(text, sizeof text, "%.0f", value);
  } else {
    std::snprintf(text, sizeof text, "%.10g", value);
  }
  return text;
}

namespace {

void check_range(const io::YamlMap& map, std::string_view key, double value, const Range& range) {
  if (!range.contains(value)) {
    map.fail(key, "must be " + range.describe() + ", not " + format_number(value));
  }
}

}  // namespace

bool reads_as_octal(std::string_view scalar) {
  if (!scalar.empty() && (scalar.front() == '-' || scalar.front() == '+')) scalar.remove_prefix(1);
  return scalar.size() > 1 && scalar.front() == '0' && scalar[1] >= '0' && scalar[1] <= '9';
}

long whole_number(const io::YamlMap& map, std::string_view key) {
  const long value = map.integer(key);
  const std::string written = map.node(key).Scalar();
  if (reads_as_octal(written)) {
    map.fail(key,
             "must be written without a leading 0 (YAML would read \"" + written + "\" as octal)");
  }
  return value;
}

double required_number(const io::YamlMap& map, std::string_view key, const Range& range) {
  const double value = map.number(key);
  check_range(map, key, value, range);
  return value;
}

double number(const io::YamlMap& map, std::string_view key, const Range& range, double fallback) {
  return map.has(key) ? required_number(map, key, range) : fallback;
}

std::optional<double> optional_number(const io::YamlMap& map, std::string_view key,
                                      const Range& range) {
  if (!map.has(key)) return std::nullopt;
  return required_number(map, key, range);
}

long required_integer(const io::YamlMap& map, std::string_view key, const Range& range) {
  const long value = whole_number(map, key);
  check_range(map, key, static_cast<double>(value), range);
  return value;
}

long integer(const io::YamlMap& map, std::string_view key, const Range& range, long fallback) {
  return map.has(key) ? required_integer(map, key, range) : fallback;
}

std::optional<long> optional_integer(const io::YamlMap& map, std::string_view key,
                                     const Range& range) {
  if (!map.has(key)) return std::nullopt;
  return required_integer(map, key, range);
}

std::chrono::milliseconds milliseconds(const io::YamlMap& map, std::string_view key,
                                       const Range& range, std::chrono::milliseconds fallback) {
  return std::chrono::milliseconds(integer(map, key, range, fallback.count()));
}

namespace {

template <class T>
[[noreturn]] void fail_value_choice(const io::YamlMap& map, std::string_view key, T got,
                                    std::initializer_list<T> allowed) {
  std::string list;
  for (const T a : allowed) list += (list.empty() ? "" : ", ") + format_number(a);
  map.fail(key, "must be one of " + list + ", not " + format_number(got));
}

}  // namespace

long integer_choice(const io::YamlMap& map, std::string_view key,
                    std::initializer_list<long> allowed, long fallback) {
  if (!map.has(key)) return fallback;
  const long value = whole_number(map, key);
  for (const long a : allowed) {
    if (a == value) return value;
  }
  fail_value_choice(map, key, value, allowed);
}

double number_choice(const io::YamlMap& map, std::string_view key,
                     std::initializer_list<double> allowed, double fallback) {
  if (!map.has(key)) return fallback;
  const double value = map.number(key);
  for (const double a : allowed) {
    if (a == value) return value;
  }
  fail_value_choice(map, key, value, allowed);
}

void fail_choice(const io::YamlMap& map, std::string_view key, std::string_view got,
                 const std::vector<std::string_view>& names) {
  std::string list;
  for (const auto name : names) list += (list.empty() ? "" : ", ") + std::string(name);
  map.fail(key, "must be one of " + list + ", not \"" + std::string(got) + "\"");
}

std::string required_text(const io::YamlMap& map, std::string_view key) {
  std::string value = map.text(key);
  if (value.empty()) map.fail(key, "must not be empty");
  return value;
}

std::string text(const io::YamlMap& map, std::string_view key, std::string fallback) {
  return map.has(key) ? required_text(map, key) : std::move(fallback);
}

std::filesystem::path resolve_path(const std::filesystem::path& path,
                                   const std::filesystem::path& base) {
  if (path.empty() || path.is_absolute()) return path.lexically_normal();
  return (base / path).lexically_normal();
}

std::filesystem::path required_path(const io::YamlMap& map, std::string_view key,
                                    const std::filesystem::path& base) {
  const std::string value = map.text(key);
  if (value.empty()) map.fail(key, "must be a path, not empty");
  if (value.find('\0') != std::string::npos) map.fail(key, "must not contain a NUL character");
  return resolve_path(value, base);
}

std::filesystem::path path(const io::YamlMap& map, std::string_view key,
                           const std::filesystem::path& base, std::filesystem::path fallback) {
  return map.has(key) ? required_path(map, key, base) : std::move(fallback);
}

unsigned octal_mode(const io::YamlMap& map, std::string_view key, unsigned fallback) {
  if (!map.has(key)) return fallback;
  const std::string value = map.text(key);
  std::string_view digits = value;
  if (digits.size() == 4 && digits.front() == '0') digits.remove_prefix(1);
  bool octal = digits.size() == 3;
  unsigned mode = 0;
  for (const char c : digits) {
    octal = octal && c >= '0' && c <= '7';
    mode = mode * 8 + static_cast<unsigned>(c - '0');
  }
  if (!octal) map.fail(key, "must be an octal mode like \"0660\", not \"" + value + "\"");
  return mode;
}

std::string format_octal_mode(unsigned mode) {
  char text[16];
  std::snprintf(text, sizeof text, "%04o", mode);
  return text;
}

std::optional<io::YamlMap> section(const io::YamlMap& parent, std::string_view key,
                                   std::initializer_list<std::string_view> allowed) {
  if (!parent.has(key)) return std::nullopt;
  const YAML::Node node = parent.node(key);
  if (node.IsNull()) return std::nullopt;
  return io::YamlMap(node, parent.child_path(key), allowed);
}

}  // namespace tofcomp::io::fields
