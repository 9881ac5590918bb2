// logging.level and logging.target of tofcompd.yaml (docs/configuration.md): how much the daemon
// logs and where (daemon/service/logging.hpp acts on them).
#pragma once

#include <spdlog/common.h>

#include <string_view>

namespace tofcomp::settings {

enum class LogTarget {
  Auto,     // the journal when stderr is connected to it, otherwise stderr
  Journal,  // sd_journal_send(3)
  Stderr,   // one formatted line per message on stderr
};

// "auto", "journal", "stderr", in any case; throws core::InvalidInput naming the bad value
// otherwise.
LogTarget parse_log_target(std::string_view name);

// spdlog's level names, in any case: trace, debug, info, warn (or warning), error (or err),
// critical, off.
// Throws core::InvalidInput naming the bad value and the accepted ones.
spdlog::level::level_enum parse_log_level(std::string_view name);

}  // namespace tofcomp::settings
