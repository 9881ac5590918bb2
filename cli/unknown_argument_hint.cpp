// "Did you mean" for the arguments CLI11 left unparsed (cli/unknown_argument_hint.hpp).
#include "cli/unknown_argument_hint.hpp"

#include <algorithm>
#include <vector>

#include "io/closest_names.hpp"

namespace tofcomp::cli {

namespace {

// The subcommand the command line reached: the last one parsed, the app itself if none.
const CLI::App& innermost(const CLI::App& app) {
  const CLI::App* current = &app;
  while (!current->get_subcommands().empty()) current = current->get_subcommands().back();
  return *current;
}

// The full name, e.g. "tofcomp query subscribe" (the program by its file name, not its path).
std::string path_of(const CLI::App& app) {
  if (app.get_parent() == nullptr) {
    const std::string& program = app.get_name();
    return program.substr(program.rfind('/') + 1);
  }
  return path_of(*app.get_parent()) + " " + app.get_name();
}

// The options valid where the command line ended: its own and, as tofcomp's subcommands fall
// through to their parents, those of every parent.
std::vector<std::string> option_names(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::App* level = &app; level != nullptr; level = level->get_parent()) {
    for (const CLI::Option* option : level->get_options()) {
      for (const std::string& name : option->get_lnames()) names.push_back("--" + name);
      for (const std::string& name : option->get_snames()) names.push_back("-" + name);
    }
  }
  std::sort(names.begin(), names.end());
  names.erase(std::unique(names.begin(), names.end()), names.end());
  return names;
}

std::vector<std::string> subcommand_names(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    names.push_back(sub->get_name());
  }
  return names;
}

std::string quoted_list(const std::vector<std::string>& names) {
  std::string text;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i > 0) text += i + 1 == names.size() ? " or " : ", ";
    text += "'" + names[i] + "'";
  }
  return text;
}

}  // namespace

std::string unknown_argument_hint(const CLI::App& app) {
  const CLI::App& reached = innermost(app);
  std::string hint;
  for (std::string argument : app.remaining(true)) {
    const bool is_option = argument.size() > 1 && argument[0] == '-';
    if (is_option) argument = argument.substr(0, argument.find('='));  // --name=value
    const std::vector<std::string> near =
        io::closest_names(argument, is_option ? option_names(reached) : subcommand_names(reached));
    if (near.empty()) continue;
    hint += path_of(reached) + ": '" + argument + "' is not " +
            (is_option ? "an option" : "a subcommand") + "; did you mean " + quoted_list(near) +
            "?\n";
  }
  return hint;
}

}  // namespace tofcomp::cli
