// Writing a file so that a crash at any moment leaves either the old file or the new one,
// never a torn one: write a temporary file beside it, fsync it, rename it over the target,
// fsync the directory.
#pragma once

#include <filesystem>
#include <functional>
#include <ostream>
#include <string_view>
#include <vector>

namespace tofcomp::io {

// Throws core::Error naming the file and the system error on any failure; the temporary file
// is removed then.
void write_file_atomically(const std::filesystem::path& file, std::string_view contents);

// The same, for writers that stream: `write` fills the stream, which goes to the temporary file
// through a fixed buffer (the contents are never held in memory whole). An exception thrown by
// `write` removes the temporary file, leaves the target as it was, and propagates.
void write_file_atomically(const std::filesystem::path& file,
                           const std::function<void(std::ostream&)>& write);

// The temporary files a write of `file` interrupted by a crash left beside it (".NAME.XXXXXX",
// regular files of this user), removed; returns what it removed. Run before any write of `file`
// starts (tofcompd at start). Another file is never touched; a failure to list or remove is not
// an error (the files are harmless, only clutter).
std::vector<std::filesystem::path> remove_stale_temporaries(const std::filesystem::path& file);

}  // namespace tofcomp::io
