// Where tofcompd's log goes and how much of it: the systemd journal (native fields, priority
// per level) or stderr, chosen by the rule systemd documents for JOURNAL_STREAM.
#pragma once

#include <spdlog/common.h>

#include <string>
#include <string_view>

#include "settings/log_settings.hpp"

namespace tofcomp::daemon::service {

using settings::LogTarget;

// systemd.exec(5): a service's stderr goes to the journal when JOURNAL_STREAM is set and its
// "device:inode" (decimal) equals those of the stream. `journal_stream` is the variable's value
// (nullptr when unset); `fd` the stream to check.
bool stream_is_journal(const char* journal_stream, int fd);

// Auto resolved by the rule above for stderr (reading JOURNAL_STREAM); other targets as given.
LogTarget resolve_log_target(LogTarget requested);

// What the log lines of a daemon that is not an instance are identified by.
inline constexpr std::string_view kDefaultLogIdentity = "tofcompd";

// Makes a logger named `identity` writing to the resolved target at `level` spdlog's default
// logger (what spdlog::info() and friends use), and returns the target chosen. In the journal
// the identity is SYSLOG_IDENTIFIER; on stderr an identity other than the default (an
// instance's, tofcompd@NAME) starts each line.
LogTarget configure_logging(LogTarget target, spdlog::level::level_enum level,
                            const std::string& identity = std::string(kDefaultLogIdentity));

}  // namespace tofcomp::daemon::service
