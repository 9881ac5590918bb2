#include "io/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <streambuf>
#include <string>

#include "core/error.hpp"

namespace tofcomp::io {
namespace {

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& what, int error) {
  throw core::Error(file.string() + ": " + what + ": " + std::strerror(error));
}

// 0 when all was written, otherwise the errno of the failure.
int write_all(int fd, std::string_view data) {
  while (!data.empty()) {
    const ssize_t n = ::write(fd, data.data(), data.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    data.remove_prefix(static_cast<std::size_t>(n));
  }
  return 0;
}

// A stream buffer over a file descriptor that keeps the errno of the first failed write.
class DescriptorBuffer : public std::streambuf {
 public:
  explicit DescriptorBuffer(int fd) : fd_(fd) { reset(); }
  int error() const { return error_; }

 protected:
  int_type overflow(int_type ch) override {
    if (!drain()) return traits_type::eof();
    if (traits_type::eq_int_type(ch, traits_type::eof())) return traits_type::not_eof(ch);
    *pptr() = traits_type::to_char_type(ch);
    pbump(1);
    return ch;
  }
  int sync() override { return drain() ? 0 : -1; }

 private:
  void reset() { setp(buffer_.data(), buffer_.data() + buffer_.size()); }
  bool drain() {
    if (error_ == 0)
      error_ =
          write_all(fd_, std::string_view(pbase(), static_cast<std::size_t>(pptr() - pbase())));
    reset();
    return error_ == 0;
  }

  int fd_;
  int error_ = 0;
  std::array<char, 1 << 16> buffer_{};
};

// The temporary file's name beside the target: "." + the target's name + "." + mkstemp's six
// characters.
constexpr const char* kTemporarySuffix = ".XXXXXX";
constexpr std::size_t kTemporaryRandomChars = 6;

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
    if (::fchmod(fd_, 0644) != 0) fail(target_, "cannot set permissions", errno);
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
