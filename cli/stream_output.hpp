// Output of a command that streams until it is stopped (tofcomp query subscribe without -n), the
// way `gpspipe -w` does: Ctrl-C (SIGINT) or SIGTERM ends it with status 0 between two lines,
// never inside one, and a reader that goes away (`| head -n 3`) ends it with status 0 too.
#pragma once

#include <string>

namespace tofcomp::cli {

// Installs the handlers above for the rest of the process.
void end_stream_on_interrupt();

// Writes text to stdout and flushes it, with SIGINT and SIGTERM held until it is out. False
// when stdout's reader is gone (EPIPE): the stream is over.
bool write_stream_line(const std::string& text);

}  // namespace tofcomp::cli
