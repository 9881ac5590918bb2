// `--help` in GNU style for every program (tofcomp, tofcompd, the bridges), as gpsd's and
// chronyd's read: "  -c, --config=FILE" with the description beside it, wrapped to 80 columns
// (under it when the option is wide). Where CLI11 prints an option's type and checks
// ("TEXT:FILE REQUIRED", "FLOAT:1.0001 to 1000000=2"), the value gets a name in capitals (FILE,
// N, X, TEXT, or the name its check gives) and the rest is said in words at the end of the
// description: "(1.0001 to 1000000; default 2; required)".
#pragma once

#include <CLI/CLI.hpp>
#include <cstddef>
#include <string>

namespace tofcomp::io {

// The width of the help, and of its left column (the options).
inline constexpr std::size_t kHelpWidth = 80;
inline constexpr std::size_t kHelpOptionColumn = 30;

class GnuHelpFormatter : public CLI::Formatter {
 public:
  GnuHelpFormatter();
  std::string make_option(const CLI::Option* opt, bool is_positional) const override;
  std::string make_option_name(const CLI::Option* opt, bool is_positional) const override;
  std::string make_option_opts(const CLI::Option* opt) const override;
  std::string make_option_desc(const CLI::Option* opt) const override;
  std::string make_subcommand(const CLI::App* sub) const override;
  std::string make_description(const CLI::App* app) const override;
  std::string make_usage(const CLI::App* app, std::string name) const override;
  std::string make_option_usage(const CLI::Option* opt) const override;
};

// The value's name an option shows (FILE, N, X, TEXT...); empty for a flag.
std::string value_name(const CLI::Option& opt);

// `text` wrapped to lines of at most `width` columns (counted in UTF-8 characters), words kept
// whole, line breaks in it kept; each line after the first starts with `indent` spaces.
std::string wrap_text(const std::string& text, std::size_t width, std::size_t indent);

// Gives `app` the GNU formatter. Call before adding subcommands: they copy their parent's.
void use_gnu_help(CLI::App& app);

}  // namespace tofcomp::io
