// After a command line CLI11 refused: "did you mean" lines for the arguments it did not expect,
// from the options and subcommands of the (sub)command they were given to.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace tofcomp::cli {

// One line per unexpected argument that is near a known name, e.g.
// "tofcomp evaluate: '--figure' is not an option; did you mean '--figures'?\n"; empty when none
// is. Call it after app.parse threw, before anything parses again.
std::string unknown_argument_hint(const CLI::App& app);

}  // namespace tofcomp::cli
