// The broker password, read from the file broker.password_file names: never from the
// configuration itself, and never written to a log.
#pragma once

#include <filesystem>
#include <cstdint>
#include <string>

namespace tofcomp::bridges::mqtt {

// The file's first line (without its line end). The file must be a regular file of at most
// kMaxPasswordFileBytes that others cannot read (no o+r: like ssh's keys; 0600 or 0640 with the
// service's group); throws core::InvalidInput naming the file and what is wrong (never the
// password).
std::string read_password_file(const std::filesystem::path& file);

inline constexpr std::uint64_t kMaxPasswordFileBytes = 4096;

}  // namespace tofcomp::bridges::mqtt
