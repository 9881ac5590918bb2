// configure_logging: the journal or stderr, as spdlog's default logger.
#include "daemon/service/logging.hpp"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/sinks/systemd_sink.h>
#include <spdlog/spdlog.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <charconv>
#include <cstdlib>
#include <memory>
#include <string>
#include <utility>

#include "core/error.hpp"

namespace tofcomp::daemon::service {
namespace {

// One unsigned decimal number filling `text` exactly.
bool parse_decimal(std::string_view text, unsigned long long& value) {
  if (text.empty()) return false;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  return error == std::errc() && end == text.data() + text.size();
}

std::shared_ptr<spdlog::sinks::sink> make_sink(LogTarget target, const std::string& identity) {
  if (target == LogTarget::Journal) {
    // The journal stamps time, priority and identifier itself: the message goes unformatted.
    return std::make_shared<spdlog::sinks::systemd_sink_mt>(identity);
  }
  auto sink = std::make_shared<spdlog::sinks::stderr_color_sink_mt>();
  // Two instances logging to one terminal are told apart by their identity.
  sink->set_pattern(identity == kDefaultLogIdentity ? "%Y-%m-%d %H:%M:%S.%e %^%l%$ %v"
                                                    : "%Y-%m-%d %H:%M:%S.%e %n %^%l%$ %v");
  return sink;
}

}  // namespace

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

LogTarget configure_logging(LogTarget target, spdlog::level::level_enum level,
                            const std::string& identity) {
  const LogTarget chosen = resolve_log_target(target);
  auto logger = std::make_shared<spdlog::logger>(identity, make_sink(chosen, identity));
  logger->set_level(level);
  // Warnings and worse reach the journal or the terminal at once, even if the daemon dies next.
  logger->flush_on(spdlog::level::warn);
  spdlog::set_default_logger(std::move(logger));
  return chosen;
}

}  // namespace tofcomp::daemon::service
