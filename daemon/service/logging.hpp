// Where tofcompd's log goes and how much of it: the systemd journal (native fields, priority
// per level) or stderr, chosen by the rule systemd documents for JOURNAL_STREAM.
#pragma once

#include <spdlog/common.h>

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

// Makes a logger named "tofcompd" writing to the resolved target at `level` spdlog's default
// logger (what spdlog::info() and friends use), and returns the target chosen.
LogTarget configure_logging(LogTarget target, spdlog::level::level_enum level);

}  // namespace tofcomp::daemon::service
