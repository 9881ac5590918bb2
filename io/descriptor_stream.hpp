// An output stream buffer over a file descriptor that keeps the errno of the first failed write
// and counts the bytes written, so that a writer can name why it failed ("No space left on
// device") and cut a file back to what it wrote whole.
#pragma once

#include <array>
#include <cstdint>
#include <ostream>
#include <streambuf>
#include <string_view>

namespace tofcomp::io {

// 0 when all of `data` was written to fd, otherwise the errno of the failure (EINTR retried).
int write_all(int fd, std::string_view data);

class DescriptorBuffer : public std::streambuf {
 public:
  // Writes to fd, which it does not own.
  explicit DescriptorBuffer(int fd) : fd_(fd) { reset(); }
  // The errno of the first failed write; 0 while none failed. After a failure nothing more is
  // written.
  int error() const { return error_; }
  // The bytes written to the descriptor so far (not those still buffered).
  std::uint64_t written() const { return written_; }

 protected:
  int_type overflow(int_type ch) override;
  int sync() override { return drain() ? 0 : -1; }

 private:
  static constexpr std::size_t kBufferBytes = 1 << 16;
  void reset() { setp(buffer_.data(), buffer_.data() + buffer_.size()); }
  bool drain();

  int fd_;
  int error_ = 0;
  std::uint64_t written_ = 0;
  std::array<char, kBufferBytes> buffer_{};
};

// An output stream over a descriptor it owns (closed with the stream), through a
// DescriptorBuffer: the errno of its first failed write and the bytes it wrote. Destroying it
// does not flush.
class DescriptorStream : public std::ostream {
 public:
  explicit DescriptorStream(int fd);
  ~DescriptorStream() override;
  DescriptorStream(const DescriptorStream&) = delete;
  DescriptorStream& operator=(const DescriptorStream&) = delete;

  int fd() const { return fd_; }
  int error() const { return buffer_.error(); }
  std::uint64_t written() const { return buffer_.written(); }

 private:
  int fd_;
  DescriptorBuffer buffer_;
};

}  // namespace tofcomp::io
