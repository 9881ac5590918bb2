#include "sim/lms200/pty_port.hpp"

#include <fcntl.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/error.hpp"

namespace tofcomp::sim::lms200 {

namespace {
[[noreturn]] void fail(const std::string& what) {
  throw core::Error("pty: " + what + ": " + std::strerror(errno));
}
}  // namespace

PtyPort::PtyPort() {
  char name[256] = {};
  if (::openpty(&master_, &slave_, name, nullptr, nullptr) != 0) fail("openpty");
  slave_path_ = name;
  termios tio{};
  if (::tcgetattr(slave_, &tio) != 0) fail("tcgetattr on " + slave_path_);
  ::cfmakeraw(&tio);
  ::cfsetispeed(&tio, B9600);
  ::cfsetospeed(&tio, B9600);
  if (::tcsetattr(slave_, TCSANOW, &tio) != 0) fail("tcsetattr on " + slave_path_);
  const int flags = ::fcntl(master_, F_GETFL);
  if (flags < 0 || ::fcntl(master_, F_SETFL, flags | O_NONBLOCK) != 0) fail("fcntl O_NONBLOCK");
}

PtyPort::~PtyPort() {
  close();
}

void PtyPort::close() {
  if (master_ >= 0) ::close(master_);
  if (slave_ >= 0) ::close(slave_);
  master_ = slave_ = -1;
}

std::optional<unsigned> PtyPort::host_baud() const {
  termios tio{};
  if (slave_ < 0 || ::tcgetattr(slave_, &tio) != 0) return std::nullopt;
  switch (::cfgetospeed(&tio)) {
    case B9600:
      return 9600;
    case B19200:
      return 19200;
    case B38400:
      return 38400;
    case B500000:
      return 500000;
    default:
      return std::nullopt;
  }
}

void publish_symlink(const std::filesystem::path& link, const std::string& target) {
  std::filesystem::path temporary = link;
  temporary += ".new";
  std::error_code ec;
  std::filesystem::remove(temporary, ec);
  std::filesystem::create_symlink(target, temporary);
  std::filesystem::rename(temporary, link);
}

}  // namespace tofcomp::sim::lms200
