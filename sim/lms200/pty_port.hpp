// A pseudo-terminal standing in for the LMS 200's serial port: the emulator holds the master,
// the host opens the slave by its path (or by a stable symlink, re-pointed when the emulator
// simulates a hang-up). The slave is kept open here so the master never sees EOF when a host
// closes, and so the rate the host set on the line can be read back (termios is the line's).
#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace tofcomp::sim::lms200 {

class PtyPort {
 public:
  // Opens a new pty in raw mode at 9600 Bd. Throws core::Error with the errno text on failure.
  PtyPort();
  ~PtyPort();
  PtyPort(const PtyPort&) = delete;
  PtyPort& operator=(const PtyPort&) = delete;

  int master_fd() const { return master_; }
  const std::string& slave_path() const { return slave_path_; }
  // The rate the host has set on its side of the line; empty for a rate the LMS lacks.
  std::optional<unsigned> host_baud() const;
  // Closes both ends: a host reading the slave sees the line hang up.
  void close();

 private:
  int master_ = -1;
  int slave_ = -1;
  std::string slave_path_;
};

// Points `link` at `target` atomically (a temporary symlink renamed over it).
void publish_symlink(const std::filesystem::path& link, const std::string& target);

}  // namespace tofcomp::sim::lms200
