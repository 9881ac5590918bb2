#include "settings/log_settings.hpp"

#include <array>
#include <cctype>
#include <string>
#include <utility>

#include "core/error.hpp"

namespace tofcomp::settings {
namespace {

std::string lowercase(std::string_view text) {
  std::string lower(text);
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lower;
}

}  // namespace

LogTarget parse_log_target(std::string_view name) {
  const std::string lower = lowercase(name);
  if (lower == "auto") return LogTarget::Auto;
  if (lower == "journal") return LogTarget::Journal;
  if (lower == "stderr") return LogTarget::Stderr;
  throw core::InvalidInput("unknown log target '" + std::string(name) +
                           "': expected auto, journal or stderr");
}

spdlog::level::level_enum parse_log_level(std::string_view name) {
  static constexpr std::array<std::pair<std::string_view, spdlog::level::level_enum>, 9> kNames{{
      {"trace", spdlog::level::trace},
      {"debug", spdlog::level::debug},
      {"info", spdlog::level::info},
      {"warn", spdlog::level::warn},
      {"warning", spdlog::level::warn},
      {"error", spdlog::level::err},
      {"err", spdlog::level::err},
      {"critical", spdlog::level::critical},
      {"off", spdlog::level::off},
  }};
  const std::string lower = lowercase(name);
  for (const auto& [known, level] : kNames) {
    if (lower == known) return level;
  }
  throw core::InvalidInput("unknown log level '" + std::string(name) +
                           "': expected trace, debug, info, warn, error, critical or off");
}

}  // namespace tofcomp::settings
