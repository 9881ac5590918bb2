// The text of tofcompd.yaml to one YAML document.
#include "settings/yaml_document.hpp"

#include <yaml-cpp/eventhandler.h>

#include <algorithm>
#include <optional>
#include <sstream>

#include "settings/daemon_config_error.hpp"

namespace tofcomp::settings {

namespace {

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

}  // namespace

std::string yaml_position(const std::string& source, const YAML::Mark& mark) {
  if (mark.is_null()) return source;
  return source + ":" + std::to_string(mark.line + 1) + ":" + std::to_string(mark.column + 1);
}

YAML::Node load_single_yaml_document(std::string_view text, const std::string& source) {
  if (const std::size_t nul = text.find('\0'); nul != std::string_view::npos) {
    YAML::Mark mark;
    mark.line = static_cast<int>(
        std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(nul), '\n'));
    const std::size_t line_start = nul == 0 ? std::string_view::npos : text.rfind('\n', nul - 1);
    mark.column =
        static_cast<int>(line_start == std::string_view::npos ? nul : nul - line_start - 1);
    throw DaemonConfigError(yaml_position(source, mark) +
                            ": a NUL byte: a configuration is text, and what follows a NUL would "
                            "be lost");
  }
  const std::string copy(text);
  try {
    // At most two documents are asked for: the second is an error wherever it comes from.
    std::istringstream in(copy);
    YAML::Parser parser(in);
    DocumentStarts starts;
    if (parser.HandleNextDocument(starts) && parser.HandleNextDocument(starts)) {
      throw DaemonConfigError(
          yaml_position(source, starts.last_start.value_or(YAML::Mark::null_mark())) +
          ": YAML syntax error: text after the end of the document (a second document, or a "
          "line YAML cannot read)");
    }
    return YAML::Load(copy);
  } catch (const YAML::ParserException& e) {
    throw DaemonConfigError(yaml_position(source, e.mark) + ": YAML syntax error: " + e.msg);
  }
}

}  // namespace tofcomp::settings
