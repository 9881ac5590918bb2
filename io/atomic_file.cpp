#include "io/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <streambuf>
#include <string>
#include <utility>

#include "core/error.hpp"
#include "io/descriptor_stream.hpp"

namespace tofcomp::io {
namespace {

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& what, int error) {
  throw core::Error(file.string() + ": " + what + ": " + std::strerror(error));
}

// The temporary file's name beside the target: "." + the target's name + "." + mkstemp's six
// characters.
constexpr const char* kTemporarySuffix = ".XXXXXX";
constexpr std::size_t kTemporaryRandomChars = 6;
constexpr mode_t kFileMode = 0644;  // the files written: the owner writes, everyone reads

std::string temporary_prefix(const std::filesystem::path& target) {
  return "." + target.filename().string() + ".";
}

// The temporary file beside the target; removed on destruction unless renamed over it.
class TemporaryFile {
 public:
  explicit TemporaryFile(const std::filesystem::path& target)
      : target_(target),
        path_(
            (target.parent_path() / (temporary_prefix(target) + (kTemporarySuffix + 1))).string()),
        fd_(::mkstemp(path_.data())) {
    if (fd_ < 0) fail(target_, "cannot create a temporary file beside it", errno);
  }
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;
  ~TemporaryFile() {
    if (fd_ >= 0) ::close(fd_);
    if (!renamed_) ::unlink(path_.c_str());
  }

  int fd() const { return fd_; }

  // Syncs and closes the temporary file, renames it over the target, syncs the directory.
  void commit() {
    if (::fchmod(fd_, kFileMode) != 0) fail(target_, "cannot set permissions", errno);
    if (::fsync(fd_) != 0) fail(target_, "cannot sync", errno);
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0) fail(target_, "cannot close", errno);
    if (::rename(path_.c_str(), target_.c_str()) != 0) {
      fail(target_, "cannot rename the temporary file over it", errno);
    }
    renamed_ = true;
    sync_directory();
  }

  // Renames the (empty) temporary file over the target at once and hands over its descriptor,
  // open for writing: the caller owns it.
  int release_at_target() {
    if (::fchmod(fd_, kFileMode) != 0) fail(target_, "cannot set permissions", errno);
    if (::rename(path_.c_str(), target_.c_str()) != 0) {
      fail(target_, "cannot rename a new file over it", errno);
    }
    renamed_ = true;
    sync_directory();
    return std::exchange(fd_, -1);
  }

 private:
  void sync_directory() const {
    const std::filesystem::path dir = target_.parent_path();
    const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) fail(target_, "cannot open its directory to sync it", errno);
    const int rc = ::fsync(fd);
    const int error = errno;
    ::close(fd);
    if (rc != 0) fail(target_, "cannot sync its directory", error);
  }

  std::filesystem::path target_;
  std::string path_;
  int fd_;
  bool renamed_ = false;
};

}  // namespace

void write_file_atomically(const std::filesystem::path& file, std::string_view contents) {
  write_file_atomically(file, [&](std::ostream& out) {
    out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
  });
}

void write_file_atomically(const std::filesystem::path& file,
                           const std::function<void(std::ostream&)>& write) {
  TemporaryFile temporary(file);
  DescriptorBuffer buffer(temporary.fd());
  std::ostream out(&buffer);
  try {
    write(out);
    out.flush();
  } catch (...) {  // a writer that stops on a failed stream: report why the stream failed
    if (buffer.error() != 0) fail(file, "cannot write", buffer.error());
    throw;
  }
  if (buffer.error() != 0) fail(file, "cannot write", buffer.error());
  if (!out) throw core::Error(file.string() + ": the stream failed while writing");
  temporary.commit();
}

int replace_with_new_file(const std::filesystem::path& file) {
  TemporaryFile temporary(file);
  return temporary.release_at_target();
}

std::optional<int> create_new_file(const std::filesystem::path& file) {
  const int fd =
      ::open(file.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, kFileMode);
  if (fd >= 0) return fd;
  if (errno == EEXIST) return std::nullopt;
  fail(file, "cannot create it", errno);
}

std::vector<std::filesystem::path> remove_stale_temporaries(const std::filesystem::path& file) {
  std::vector<std::filesystem::path> removed;
  const std::filesystem::path dir = file.parent_path().empty() ? "." : file.parent_path();
  const std::string prefix = temporary_prefix(file);
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(dir, error)) {
    const std::string name = entry.path().filename().string();
    if (name.size() != prefix.size() + kTemporaryRandomChars || !name.starts_with(prefix)) continue;
    const std::string random = name.substr(prefix.size());
    if (random.find_first_not_of(
            "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789") !=
        std::string::npos) {
      continue;
    }
    struct stat st {};
    if (::lstat(entry.path().c_str(), &st) != 0 || !S_ISREG(st.st_mode) ||
        st.st_uid != ::geteuid()) {
      continue;
    }
    if (::unlink(entry.path().c_str()) == 0) removed.push_back(entry.path());
  }
  return removed;
}

}  // namespace tofcomp::io
