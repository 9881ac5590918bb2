// Writing a file so that a crash at any moment leaves either the old file or the new one,
// never a torn one: write a temporary file beside it, fsync it, rename it over the target,
// fsync the directory.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
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

// Files written as they grow (tofcompd's recordings) in a directory others may write to: made
// new, never opened through a symlink or over a file planted there.
//
// A new empty file at `file` (mode 0644), open for writing; the caller owns the descriptor.
// What was at `file` (a file, or a symlink, which is replaced, not followed) is replaced by a
// rename: the new file is made under a temporary name beside it (O_EXCL), then renamed over it.
// Throws core::Error naming the file and the system error.
int replace_with_new_file(const std::filesystem::path& file);
// A new empty file at `file` (O_CREAT | O_EXCL | O_NOFOLLOW, mode 0644), open for writing;
// nullopt when the name is taken (by anything, a symlink included). Throws core::Error naming
// the file and the system error for any other failure.
std::optional<int> create_new_file(const std::filesystem::path& file);

// The temporary files a write of `file` interrupted by a crash left beside it (".NAME.XXXXXX",
// regular files of this user), removed; returns what it removed. Run before any write of `file`
// starts (tofcompd at start). Another file is never touched; a failure to list or remove is not
// an error (the files are harmless, only clutter).
std::vector<std::filesystem::path> remove_stale_temporaries(const std::filesystem::path& file);

}  // namespace tofcomp::io
