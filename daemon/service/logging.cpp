// configure_logging: the journal or stderr, as spdlog's default logger.
#include "daemon/service/logging.hpp"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/sinks/systemd_sink.h>
#include <spdlog/spdlog.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cctype>
#include <charconv>
#include <cstdlib>
#include <memory>
#include <string>
#include <utility>

#include "core/error.hpp"

namespace tofcomp::daemon::service {
namespace {

constexpr const char* kLoggerName = "tofcompd";

// One unsigned decimal number filling `text` exactly.
bool parse_decimal(std::string_view text, unsigned long long& value) {
  if (text.empty()) return false;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  return error == std::errc() && end == text.data() + text.size();
}

std::string lowercase(std::string_view text) {
  std::string lower(text);
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lower;
}

std::shared_ptr<spdlog::sinks::sink> make_sink(LogTarget target) {
  if (target == LogTarget::Journal) {
    // The journal stamps time, priority and identifier itself: the message goes unformatted.
    return std::make_shared<spdlog::sinks::systemd_sink_mt>(kLoggerName);
  }
  auto sink = std::make_shared<spdlog::sinks::stderr_color_sink_mt>();
  sink->set_pattern("%Y-%m-%d %H:%M:%S.%e %^%l%$ %v");
  return sink;
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

bool stream_is_journal(const char* journal_stream, int fd) {
  if (journal_stream == nullptr) return false;
  const std::string_view value(journal_stream);
  const auto colon = value.find(':');
  if (colon == std::string_view::npos) return false;
  unsigned long long device = 0;
  unsigned long long inode = 0;
  if (!parse_decimal(value.substr(0, colon), device) ||
      !parse_decimal(value.substr(colon + 1), inode)) {
    return false;
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0) return false;
  return static_cast<unsigned long long>(st.st_dev) == device &&
         static_cast<unsigned long long>(st.st_ino) == inode;
}

LogTarget resolve_log_target(LogTarget requested) {
  if (requested != LogTarget::Auto) return requested;
  return stream_is_journal(std::getenv("JOURNAL_STREAM"), STDERR_FILENO) ? LogTarget::Journal
                                                                         : LogTarget::Stderr;
}

LogTarget configure_logging(LogTarget target, spdlog::level::level_enum level) {
  const LogTarget chosen = resolve_log_target(target);
  auto logger = std::make_shared<spdlog::logger>(kLoggerName, make_sink(chosen));
  logger->set_level(level);
  // Warnings and worse reach the journal or the terminal at once, even if the daemon dies next.
  logger->flush_on(spdlog::level::warn);
  spdlog::set_default_logger(std::move(logger));
  return chosen;
}

}  // namespace tofcomp::daemon::service
