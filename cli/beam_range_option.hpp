// The --beams option of `tofcomp query` and `tofcomp shm-dump`: FIRST:LAST (beam indices from 0,
// both included) or one index.
#pragma once

#include <optional>
#include <string>

#include "ipc/socket/request.hpp"

namespace tofcomp::cli {

// nullopt for an empty text (every beam). Throws core::InvalidInput naming the text when it is
// not FIRST:LAST with FIRST <= LAST or one index, each at most ipc::socket::kMaxBeamIndex.
std::optional<ipc::socket::BeamRange> parse_beam_range(const std::string& text);

}  // namespace tofcomp::cli
