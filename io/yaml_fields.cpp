#include "io/yaml_fields.hpp"

#include <cmath>
#include <sstream>

namespace tofcomp::io {

YamlMap::YamlMap(const YAML::Node& node, std::string path,
                 std::initializer_list<std::string_view> allowed)
    : YamlMap(node, std::move(path),
              std::span<const std::string_view>(allowed.begin(), allowed.size())) {}

YamlMap::YamlMap(const YAML::Node& node, std::string path,
                 std::span<const std::string_view> allowed)
    : node_(node), path_(std::move(path)) {
  if (!node_.IsMap()) {
    throw YamlSchemaError((path_.empty() ? std::string("the document") : path_) +
                          " must be a mapping of keys to values");
  }
  for (const auto& entry : node_) {
    const std::string key = entry.first.as<std::string>();
    bool known = false;
    for (const auto candidate : allowed) known = known || candidate == key;
    if (!known) {
      std::ostringstream msg;
      msg << child_path(key) << " is not a known key; allowed here:";
      for (const auto candidate : allowed) msg << " " << candidate;
      throw YamlSchemaError(msg.str());
    }
  }
}

bool YamlMap::has(std::string_view key) const {
  return static_cast<bool>(node_[std::string(key)]);
}

std::string YamlMap::child_path(std::string_view key) const {
  return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
}

void YamlMap::fail(std::string_view key, std::string_view why) const {
  throw YamlSchemaError(child_path(key) + " " + std::string(why));
}

YAML::Node YamlMap::node(std::string_view key) const {
  const YAML::Node value = node_[std::string(key)];
  if (!value) fail(key, "is missing");
  return value;
}

double YamlMap::number(std::string_view key) const {
  const YAML::Node value = node(key);
  double out = 0.0;
  if (!value.IsScalar() || !YAML::convert<double>::decode(value, out) || !std::isfinite(out)) {
    fail(key, "must be a finite number, not '" + (value.IsScalar() ? value.Scalar() : "?") + "'");
  }
  return out;
}

long YamlMap::integer(std::string_view key) const {
  const YAML::Node value = node(key);
  long out = 0;
  if (!value.IsScalar() || !YAML::convert<long>::decode(value, out)) {
    fail(key, "must be a whole number, not '" + (value.IsScalar() ? value.Scalar() : "?") + "'");
  }
  return out;
}

bool YamlMap::boolean(std::string_view key) const {
  const YAML::Node value = node(key);
  bool out = false;
  if (!value.IsScalar() || !YAML::convert<bool>::decode(value, out)) {
    fail(key, "must be true or false");
  }
  return out;
}

std::string YamlMap::text(std::string_view key) const {
  const YAML::Node value = node(key);
  if (!value.IsScalar()) fail(key, "must be a text value");
  return value.Scalar();
}

double YamlMap::number_or(std::string_view key, double fallback) const {
  return has(key) ? number(key) : fallback;
}
long YamlMap::integer_or(std::string_view key, long fallback) const {
  return has(key) ? integer(key) : fallback;
}
bool YamlMap::boolean_or(std::string_view key, bool fallback) const {
  return has(key) ? boolean(key) : fallback;
}
std::string YamlMap::text_or(std::string_view key, std::string fallback) const {
  return has(key) ? text(key) : fallback;
}

namespace {

[[noreturn]] void syntax_error(const std::string& source, const YAML::ParserException& e) {
  std::ostringstream msg;
  msg << source << ":" << e.mark.line + 1 << ":" << e.mark.column + 1
      << ": YAML syntax error: " << e.msg;
  throw YamlSchemaError(msg.str());
}

}  // namespace

YAML::Node load_yaml_file(const std::string& file) {
  try {
    return YAML::LoadFile(file);
  } catch (const YAML::BadFile&) {
    throw YamlSchemaError(file + ": cannot be opened");
  } catch (const YAML::ParserException& e) {
    syntax_error(file, e);
  }
}

YAML::Node load_yaml_text(const std::string& text, const std::string& source) {
  try {
    return YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    syntax_error(source, e);
  }
}

}  // namespace tofcomp::io
