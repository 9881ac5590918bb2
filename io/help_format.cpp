#include "io/help_format.hpp"

#include <cctype>
#include <memory>
#include <regex>
#include <set>
#include <sstream>
#include <vector>

namespace tofcomp::io {
namespace {

// The name of a value of each of CLI11's types, where no check names it.
std::string name_of_type(const std::string& type) {
  if (type == "INT" || type == "UINT") return "N";
  if (type == "FLOAT") return "X";
  return type.empty() ? std::string("VALUE") : type;
}

// A check that names the value (CLI::ExistingFile: FILE; a validator's name in capitals:
// LEVEL, NAME, FIRST:LAST, N,N,...) rather than bounding it.
bool names_the_value(const std::string& check) {
  static const std::regex kName("[A-Z][A-Z0-9_]*([:,][A-Z][A-Z0-9_]*)*(,\\.\\.\\.)?");
  return std::regex_match(check, kName);
}

// CLI11's type name of an option split at its first ':' into the type and its check.
struct TypeAndCheck {
  std::string type;
  std::string check;
};
TypeAndCheck split_type(const CLI::Option& opt) {
  const std::string full = opt.get_type_name();
  const auto colon = full.find(':');
  if (colon == std::string::npos) return {full, ""};
  return {full.substr(0, colon), full.substr(colon + 1)};
}

// A bound in words: ">= 1" reads "at least 1".
std::string bound_in_words(std::string check) {
  if (check.rfind(">= ", 0) == 0) return "at least " + check.substr(3);
  if (check.rfind("<= ", 0) == 0) return "at most " + check.substr(3);
  if (check.rfind("> ", 0) == 0) return "above " + check.substr(2);
  if (check.rfind("< ", 0) == 0) return "below " + check.substr(2);
  return check;
}

std::size_t columns(const std::string& text) {
  std::size_t n = 0;
  for (const unsigned char c : text) n += (c & 0xC0) != 0x80 ? 1 : 0;
  return n;
}

std::string names(const std::set<CLI::Option*>& options) {
  std::string out;
  for (const CLI::Option* o : options) out += (out.empty() ? "" : ", ") + o->get_name();
  return out;
}

// A line of the help: `name` in the left column, `description` beside it (under it when the name
// reaches the column), wrapped to the width.
std::string two_columns(const std::string& name, const std::string& description) {
  std::string out = name;
  if (!description.empty()) {
    if (columns(name) + 1 > kHelpOptionColumn) {
      out += "\n" + std::string(kHelpOptionColumn, ' ');
    } else {
      out += std::string(kHelpOptionColumn - columns(name), ' ');
    }
    out += wrap_text(description, kHelpWidth - kHelpOptionColumn, kHelpOptionColumn);
  }
  return out + "\n";
}

}  // namespace

std::string value_name(const CLI::Option& opt) {
  // A flag: CLI11 gives it no type name (and takes no value).
  if (opt.get_type_size() == 0 || (opt.get_type_name().empty() && opt.get_option_text().empty())) {
    return {};
  }
  std::string text = opt.get_option_text();
  if (!text.empty()) {
    const auto first = text.find_first_not_of(' ');
    return first == std::string::npos ? std::string() : text.substr(first);
  }
  const TypeAndCheck t = split_type(opt);
  return names_the_value(t.check) ? t.check : name_of_type(t.type);
}

std::string wrap_text(const std::string& text, std::size_t width, std::size_t indent) {
  std::string out;
  std::istringstream paragraphs(text);
  std::string paragraph;
  bool first_line = true;
  while (std::getline(paragraphs, paragraph)) {
    std::istringstream words(paragraph);
    std::string word;
    std::string line;
    const auto flush = [&] {
      if (!first_line) out += "\n" + std::string(indent, ' ');
      out += line;
      first_line = false;
      line.clear();
    };
    bool any = false;
    while (words >> word) {
      any = true;
      if (!line.empty() && columns(line) + 1 + columns(word) > width) flush();
      line += (line.empty() ? "" : " ") + word;
    }
    if (!line.empty() || !any) flush();
  }
  return out;
}

GnuHelpFormatter::GnuHelpFormatter() {
  column_width(kHelpOptionColumn);
}

// A positional by its name in capitals (DATA), as in the usage line.
std::string GnuHelpFormatter::make_option_name(const CLI::Option* opt, bool is_positional) const {
  if (is_positional) {
    std::string name = opt->get_name(true, false);
    for (char& c : name) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return name;
  }
  std::string out;
  for (const std::string& s : opt->get_snames()) out += (out.empty() ? "-" : ", -") + s;
  out = out.empty() ? "    " : out + ", ";
  bool first = true;
  for (const std::string& l : opt->get_lnames()) {
    out += (first ? "--" : ", --") + l;
    first = false;
  }
  if (first && !opt->get_snames().empty()) out.resize(out.size() - 2);  // short names only
  return out;
}

std::string GnuHelpFormatter::make_option_opts(const CLI::Option* opt) const {
  const std::string value = value_name(*opt);
  if (value.empty() || opt->get_positional()) return {};
  std::string out = (opt->get_lnames().empty() ? " " : "=") + value;
  if (opt->get_expected_max() == CLI::detail::expected_max_vector_size) out += " ...";
  return out;
}

std::string GnuHelpFormatter::make_option_desc(const CLI::Option* opt) const {
  std::vector<std::string> notes;
  if (opt->get_option_text().empty()) {
    const TypeAndCheck t = split_type(*opt);
    if (!t.check.empty() && !names_the_value(t.check)) notes.push_back(bound_in_words(t.check));
  }
  const std::string description = opt->get_description();
  if (!opt->get_default_str().empty() && description.find("default") == std::string::npos) {
    notes.push_back("default " + opt->get_default_str());
  }
  if (opt->get_required() && opt->nonpositional()) notes.push_back("required");
  if (!opt->get_needs().empty()) notes.push_back("needs " + names(opt->get_needs()));
  if (!opt->get_excludes().empty()) notes.push_back("not with " + names(opt->get_excludes()));
  if (!opt->get_envname().empty()) notes.push_back("from $" + opt->get_envname() + " when unset");
  std::string out = description;
  if (!notes.empty()) {
    std::string joined;
    for (const auto& n : notes) joined += (joined.empty() ? "" : "; ") + n;
    out += (out.empty() ? "(" : " (") + joined + ")";
  }
  return out;
}

std::string GnuHelpFormatter::make_option(const CLI::Option* opt, bool is_positional) const {
  return two_columns("  " + make_option_name(opt, is_positional) + make_option_opts(opt),
                     make_option_desc(opt));
}

std::string GnuHelpFormatter::make_subcommand(const CLI::App* sub) const {
  return two_columns("  " + sub->get_display_name(true), sub->get_description());
}

std::string GnuHelpFormatter::make_description(const CLI::App* app) const {
  const std::string description = CLI::Formatter::make_description(app);
  return description.empty() ? description : wrap_text(description, kHelpWidth, 0) + "\n";
}

std::string GnuHelpFormatter::make_usage(const CLI::App* app, std::string name) const {
  std::string usage = CLI::Formatter::make_usage(app, std::move(name));
  while (!usage.empty() && usage.back() == '\n') usage.pop_back();
  return wrap_text(usage, kHelpWidth, 2) + "\n";
}

// A positional in the usage line: its name in capitals, in brackets when it may be left out.
std::string GnuHelpFormatter::make_option_usage(const CLI::Option* opt) const {
  std::string out = make_option_name(opt, true);
  if (opt->get_expected_max() >= CLI::detail::expected_max_vector_size) out += "...";
  return opt->get_required() ? out : "[" + out + "]";
}

void use_gnu_help(CLI::App& app) {
  app.formatter(std::make_shared<GnuHelpFormatter>());
}

}  // namespace tofcomp::io
