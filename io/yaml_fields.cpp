#include "io/yaml_fields.hpp"

#include <yaml-cpp/eventhandler.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <sstream>

#include "io/checked_file.hpp"

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

// No file of the project's YAML (calibration, datasheet, scenario) comes near it.
constexpr std::uint64_t kMaxYamlFileBytes = 16u << 20;

[[noreturn]] void syntax_error(const std::string& source, const YAML::ParserException& e) {
  throw YamlSchemaError(yaml_position(source, e.mark) + ": YAML syntax error: " + e.msg);
}

// Takes the parser's events without building anything; remembers where a document starts.
class DocumentStarts : public YAML::EventHandler {
 public:
  std::optional<YAML::Mark> last_start;

  void OnDocumentStart(const YAML::Mark& mark) override { last_start = mark; }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark&, YAML::anchor_t) override {}
  void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t,
                const std::string&) override {}
  void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t,
                       YAML::EmitterStyle::value) override {}
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t,
                  YAML::EmitterStyle::value) override {}
  void OnMapEnd() override {}
};

// What YamlMap cannot see once the document is built: a key given twice in one mapping (YAML
// forbids it; yaml-cpp would keep one silently), a key that is not plain text, nesting or size
// beyond any file of ours.
class ShapeCheck {
 public:
  ShapeCheck(const std::string& source, const YamlShapeLimits& limits)
      : source_(source), limits_(limits) {}

  void check(const YAML::Node& node, const std::string& path, int depth) {
    if (depth > limits_.max_depth) {
      throw YamlSchemaError(yaml_position(source_, node.Mark()) + ": " + path +
                            " nests deeper than " + std::to_string(limits_.max_depth) + " levels");
    }
    if (++values_ > limits_.max_values) {
      throw YamlSchemaError(source_ + ": holds more than " + std::to_string(limits_.max_values) +
                            " values (aliases counted each time)");
    }
    if (node.IsMap()) {
      std::set<std::string> seen;
      for (const auto& entry : node) {
        if (!entry.first.IsScalar()) {
          throw YamlSchemaError(yaml_position(source_, entry.first.Mark()) + ": " +
                                (path.empty() ? std::string("the document") : path) +
                                " has a key that is not plain text");
        }
        const std::string& key = entry.first.Scalar();
        const std::string child = path.empty() ? key : path + "." + key;
        if (!seen.insert(key).second) {
          throw YamlSchemaError(yaml_position(source_, entry.first.Mark()) + ": " + child +
                                " is given twice");
        }
        check(entry.second, child, depth + 1);
      }
    } else if (node.IsSequence()) {
      for (std::size_t i = 0; i < node.size(); ++i) {
        check(node[i], path + "[" + std::to_string(i) + "]", depth + 1);
      }
    }
  }

 private:
  const std::string& source_;
  const YamlShapeLimits& limits_;
  long values_ = 0;
};

// The line and column of byte `offset` of text, as YAML marks count them (from 0).
YAML::Mark mark_at(const std::string& text, std::size_t offset) {
  YAML::Mark mark;
  mark.pos = static_cast<int>(offset);
  mark.line = static_cast<int>(
      std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(offset), '\n'));
  const std::size_t line_start = text.rfind('\n', offset == 0 ? 0 : offset - 1);
  mark.column = static_cast<int>(
      line_start == std::string::npos || offset == 0 ? offset : offset - line_start - 1);
  return mark;
}

}  // namespace

std::string yaml_position(const std::string& source, const YAML::Mark& mark) {
  if (mark.is_null()) return source;
  return source + ":" + std::to_string(mark.line + 1) + ":" + std::to_string(mark.column + 1);
}

YAML::Node load_yaml_file(const std::string& file) {
  std::string text;
  try {
    const CheckedFile checked =
        open_checked_file(file, kMaxYamlFileBytes, "YAML file", "the largest YAML file read");
    text = read_checked_file(checked, kMaxYamlFileBytes, "YAML file", "the largest YAML file read");
  } catch (const core::Error& e) {
    throw YamlSchemaError(file + ": cannot be opened: " + e.what());
  }
  return load_yaml_text(text, file);
}

YAML::Node load_yaml_text(const std::string& text, const std::string& source,
                          const YamlShapeLimits& limits) {
  if (const std::size_t nul = text.find('\0'); nul != std::string::npos) {
    throw YamlSchemaError(yaml_position(source, mark_at(text, nul)) +
                          ": a NUL byte: a YAML file is text, and what follows a NUL would be "
                          "lost");
  }
  try {
    // At most two documents are asked for: the second is an error wherever it comes from.
    std::istringstream in(text);
    YAML::Parser parser(in);
    DocumentStarts starts;
    if (parser.HandleNextDocument(starts) && parser.HandleNextDocument(starts)) {
      throw YamlSchemaError(
          yaml_position(source, starts.last_start.value_or(YAML::Mark::null_mark())) +
          ": YAML syntax error: text after the end of the document (a second document, or a "
          "line YAML cannot read)");
    }
    const YAML::Node document = YAML::Load(text);
    ShapeCheck(source, limits).check(document, "", 0);
    return document;
  } catch (const YAML::ParserException& e) {
    syntax_error(source, e);
  }
}

}  // namespace tofcomp::io
