#include "io/descriptor_stream.hpp"

#include <unistd.h>

#include <cerrno>

namespace tofcomp::io {

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

DescriptorBuffer::int_type DescriptorBuffer::overflow(int_type ch) {
  if (!drain()) return traits_type::eof();
  if (traits_type::eq_int_type(ch, traits_type::eof())) return traits_type::not_eof(ch);
  *pptr() = traits_type::to_char_type(ch);
  pbump(1);
  return ch;
}

bool DescriptorBuffer::drain() {
  const std::size_t pending = static_cast<std::size_t>(pptr() - pbase());
  if (error_ == 0) {
    error_ = write_all(fd_, std::string_view(pbase(), pending));
    if (error_ == 0) written_ += pending;
  }
  reset();
  return error_ == 0;
}

DescriptorStream::DescriptorStream(int fd) : std::ostream(nullptr), fd_(fd), buffer_(fd) {
  rdbuf(&buffer_);
}

DescriptorStream::~DescriptorStream() {
  ::close(fd_);
}

}  // namespace tofcomp::io
