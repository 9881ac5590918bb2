// The --beams option of `tofcomp query` and `tofcomp shm-dump`: FIRST:LAST (beam indices from 0,
// both included) or one index.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "ipc/socket/request.hpp"

namespace tofcomp::cli {

// nullopt for an empty text (every beam). Throws core::InvalidInput naming the text when it is
// not FIRST:LAST with FIRST <= LAST or one index, each at most ipc::socket::kMaxBeamIndex.
std::optional<ipc::socket::BeamRange> parse_beam_range(const std::string& text);

// --beams=FIRST:LAST, one registration for every command that takes it: checked while the
// command line is read (a bad range is a usage error, status 2, before any work).
CLI::Option* add_beams_option(CLI::App& cmd, std::string& beams);

}  // namespace tofcomp::cli
