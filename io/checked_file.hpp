// Opening a file that someone else named (a client, a configuration) as a service must before it
// trusts it: a regular file (not a FIFO that would block a reader forever, not a device such as
// /dev/zero that never ends, not a directory or socket), opened without blocking (O_NONBLOCK, so
// that opening a FIFO cannot hang), no larger than a cap; and when it must lie in a directory,
// reached without following a symbolic link (O_NOFOLLOW), so that no link leads out. The checks are
// made on the open descriptor (fstat), and the descriptor is what is read, so the file cannot be
// swapped between the check and the read.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>

namespace tofcomp::io {

// An open, checked file; owns its descriptor.
class CheckedFile {
 public:
  CheckedFile() = default;
  CheckedFile(int fd, std::uint64_t size, std::filesystem::path path);
  CheckedFile(CheckedFile&& other) noexcept;
  CheckedFile& operator=(CheckedFile&& other) noexcept;
  CheckedFile(const CheckedFile&) = delete;
  CheckedFile& operator=(const CheckedFile&) = delete;
  ~CheckedFile();

  int fd() const { return fd_; }
  // Gives the descriptor up: the caller closes it.
  int release() { return std::exchange(fd_, -1); }
  std::uint64_t size() const { return size_; }  // when it was checked
  const std::filesystem::path& path() const { return path_; }

 private:
  int fd_ = -1;
  std::uint64_t size_ = 0;
  std::filesystem::path path_;
};

// `what` names the file in messages ("recording", "datasheet"); `cap_name` the setting that sets
// max_bytes ("recalibration.limits.recording_mib"). Each throws core::InvalidInput naming the path
// and what is wrong: it does not exist, is a FIFO, a device, a directory, is larger than
// max_bytes, or cannot be opened (the system's reason). A link is followed (the configuration's
// own paths may be links).
CheckedFile open_checked_file(const std::filesystem::path& path, std::uint64_t max_bytes,
                              const std::string& what, const std::string& cap_name);

// The same for a file that must lie directly in `directory` (absolute): `file` is taken as is
// when absolute, else from the directory; after lexical normalisation its parent must be the
// directory itself (no "..", no subdirectory), and it is opened relative to the directory's own
// descriptor without following a link, so that no link leads out: a link is refused.
// `directory_name` names the setting of the directory in messages.
CheckedFile open_checked_file_in(const std::filesystem::path& directory,
                                 const std::filesystem::path& file, std::uint64_t max_bytes,
                                 const std::string& what, const std::string& cap_name,
                                 const std::string& directory_name);

// Reads a checked file from its start: all of it, and no more than max_bytes (a file that grew
// past the cap since it was checked is refused too). Throws core::Error on a failed read.
std::string read_checked_file(const CheckedFile& file, std::uint64_t max_bytes,
                              const std::string& what, const std::string& cap_name);

}  // namespace tofcomp::io
