// Strict reading of YAML documents (scenarios, calibration files, the daemon's config): every
// error names the key path ("thermal.r1_k_per_w") and the reason, and an unknown key is an
// error, so a typo never silently falls back to a default.
#pragma once

#include <yaml-cpp/yaml.h>

#include <initializer_list>
#include <span>
#include <string>
#include <string_view>

#include "core/error.hpp"

namespace tofcomp::io {

// A YAML document that does not fit its schema. The message starts with the source and path.
class YamlSchemaError : public core::Error {
 public:
  explicit YamlSchemaError(const std::string& what) : core::Error(what) {}
};

// A mapping node at a key path, checked against the keys its schema allows.
class YamlMap {
 public:
  // Throws YamlSchemaError unless node is a mapping whose keys are all in `allowed`.
  YamlMap(const YAML::Node& node, std::string path,
          std::initializer_list<std::string_view> allowed);
  YamlMap(const YAML::Node& node, std::string path, std::span<const std::string_view> allowed);

  bool has(std::string_view key) const;
  const std::string& path() const { return path_; }
  std::string child_path(std::string_view key) const;

  // Required values: a missing key or a value of the wrong type is an error naming the path.
  double number(std::string_view key) const;
  long integer(std::string_view key) const;
  bool boolean(std::string_view key) const;
  std::string text(std::string_view key) const;
  YAML::Node node(std::string_view key) const;

  // Optional values: the fallback when the key is absent, an error when present but wrong.
  double number_or(std::string_view key, double fallback) const;
  long integer_or(std::string_view key, long fallback) const;
  bool boolean_or(std::string_view key, bool fallback) const;
  std::string text_or(std::string_view key, std::string fallback) const;

  [[noreturn]] void fail(std::string_view key, std::string_view why) const;

 private:
  YAML::Node node_;
  std::string path_;
};

// How deep and how large a document may be: beyond either it is refused before it can cost
// much (a deeply nested, self-referencing or alias-multiplied one, "billion laughs"). No file of
// the project's YAML (calibration, datasheet, scenario) comes near the defaults.
struct YamlShapeLimits {
  int max_depth = 32;
  long max_values = 1000000;  // aliases counted each time they are used
};

// "calibration.yaml:12:3" (1-based), or just the source when the mark is unknown.
std::string yaml_position(const std::string& source, const YAML::Mark& mark);

// Loads a YAML file; a missing file or a syntax error is a YamlSchemaError naming the file and
// the line. Strict beyond YAML's syntax: the file must be a regular file of at most 16 MiB
// (io/checked_file.hpp: no FIFO, device or link), hold one document, no NUL byte, no key twice in
// a mapping, no key that is not plain text, and stay within the default YamlShapeLimits.
YAML::Node load_yaml_file(const std::string& file);
// The same for text in memory; `source` names it in errors. Text without a document (empty,
// comments only) gives a null node.
YAML::Node load_yaml_text(const std::string& text, const std::string& source,
                          const YamlShapeLimits& limits = {});

}  // namespace tofcomp::io
