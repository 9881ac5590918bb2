// The text of tofcompd.yaml to one YAML document: a syntax error, or text after the first
// document, is a DaemonConfigError naming the source, line and column. Works around yaml-cpp
// 0.7's YAML::LoadAll, which on some malformed input reports documents without end.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>
#include <string_view>

namespace tofcomp::settings {

// "tofcompd.yaml:12:3" (1-based), or just the source when the mark is unknown.
std::string yaml_position(const std::string& source, const YAML::Mark& mark);

// The document's root: a null node when the text holds no document (empty, comments only).
YAML::Node load_single_yaml_document(std::string_view text, const std::string& source);

}  // namespace tofcomp::settings
