// Helpers of the ring tests: unique shm names that are removed afterwards, scans whose every
// value is a known function of (sequence, beam index) so that a copy mixing two scans is
// detected, and raw read-write access to a ring's bytes (to corrupt headers on purpose).
#pragma once

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>

#include "ipc/compensated_scan.hpp"

namespace tofcomp::ipc::ring::testing {

// A name no other test (or concurrent test run) uses; removed when this goes out of scope.
class ScopedRingName {
 public:
  explicit ScopedRingName(const std::string& tag) {
    static std::atomic<int> counter{0};
    name_ =
        "/tofcomp-test-" + std::to_string(::getpid()) + "-" + tag + "-" + std::to_string(counter++);
    ::shm_unlink(name_.c_str());
  }
  ~ScopedRingName() { ::shm_unlink(name_.c_str()); }
  ScopedRingName(const ScopedRingName&) = delete;
  ScopedRingName& operator=(const ScopedRingName&) = delete;
  const std::string& str() const { return name_; }
  operator const std::string&() const { return name_; }

 private:
  std::string name_;
};

// Values that identify (sequence, beam): exact in double and float.
inline double known_raw_mm(std::uint64_t sequence, std::size_t beam) {
  return 100000.0 * static_cast<double>(sequence % 1000000) + static_cast<double>(beam);
}

inline CompensatedScan known_scan(std::uint64_t sequence, std::size_t beam_count) {
  CompensatedScan scan;
  scan.sequence = sequence;
  scan.device_sequence = 3 * sequence + 7;
  scan.timestamp_ns = 1'700'000'000'000'000'000 + static_cast<std::int64_t>(sequence) * 13'333'333;
  scan.junction_c = 25.0 + 0.25 * static_cast<double>(sequence % 64);
  scan.junction_std_c = 0.125;
  scan.case_c = 20.0 + 0.5 * static_cast<double>(sequence % 32);
  scan.start_angle_deg = -0.5 * static_cast<double>(sequence % 4);
  scan.resolution_deg = 0.5;
  scan.calibration_id = static_cast<std::uint32_t>(sequence % 97);
  scan.rays = {scan.timestamp_ns - 34'603'704, 37037.037037037036, 13333333.333333334, 2};
  scan.beams.resize(beam_count);
  for (std::size_t b = 0; b < beam_count; ++b) {
    BeamValue& v = scan.beams[b];
    v.raw_mm = known_raw_mm(sequence, b);
    v.compensated_mm = v.raw_mm - 0.5;
    v.window_mm = v.raw_mm - 0.25;
    v.window_std_mm = 0.125 * static_cast<double>(b % 8);
    v.mode_posterior = {static_cast<float>(sequence % 1000), static_cast<float>(b % 1000), 0.25f,
                        0.125f};
    v.flags = static_cast<std::uint16_t>((sequence + b) & 0x1F);
    v.mode_count = static_cast<std::uint8_t>(1 + sequence % 4);
    v.most_probable_mode = static_cast<std::uint8_t>(b % (1 + sequence % 4));
  }
  return scan;
}

inline bool same_double(double a, double b) {
  return (std::isnan(a) && std::isnan(b)) || a == b;
}

// "" if `got` equals `want` field by field (NaN equal to NaN), else the first difference.
inline std::string difference(const CompensatedScan& got, const CompensatedScan& want) {
  const auto scalar = [](const char* field, double a, double b) -> std::string {
    return same_double(a, b)
               ? ""
               : std::string(field) + " " + std::to_string(a) + " != " + std::to_string(b);
  };
  if (got.sequence != want.sequence) return "sequence differs";
  if (got.device_sequence != want.device_sequence) return "device_sequence differs";
  if (got.timestamp_ns != want.timestamp_ns) return "timestamp_ns differs";
  if (got.calibration_id != want.calibration_id) return "calibration_id differs";
  if (got.rays.first_ray_ns != want.rays.first_ray_ns) return "rays.first_ray_ns differs";
  if (got.rays.interlaced_turns != want.rays.interlaced_turns) {
    return "rays.interlaced_turns differs";
  }
  for (const std::string& d :
       {scalar("junction_c", got.junction_c, want.junction_c),
        scalar("junction_std_c", got.junction_std_c, want.junction_std_c),
        scalar("case_c", got.case_c, want.case_c),
        scalar("start_angle_deg", got.start_angle_deg, want.start_angle_deg),
        scalar("resolution_deg", got.resolution_deg, want.resolution_deg),
        scalar("rays.ray_interval_ns", got.rays.ray_interval_ns, want.rays.ray_interval_ns),
        scalar("rays.turn_period_ns", got.rays.turn_period_ns, want.rays.turn_period_ns)}) {
    if (!d.empty()) return d;
  }
  if (got.beams.size() != want.beams.size()) {
    return "beam count " + std::to_string(got.beams.size()) +
           " != " + std::to_string(want.beams.size());
  }
  for (std::size_t b = 0; b < got.beams.size(); ++b) {
    const BeamValue& g = got.beams[b];
    const BeamValue& w = want.beams[b];
    const std::string at = "beam " + std::to_string(b) + ": ";
    if (!same_double(g.raw_mm, w.raw_mm)) return at + "raw_mm";
    if (!same_double(g.compensated_mm, w.compensated_mm)) return at + "compensated_mm";
    if (!same_double(g.window_mm, w.window_mm)) return at + "window_mm";
    if (!same_double(g.window_std_mm, w.window_std_mm)) return at + "window_std_mm";
    for (int m = 0; m < kMaxModes; ++m) {
      if (std::memcmp(&g.mode_posterior[m], &w.mode_posterior[m], sizeof(float)) != 0) {
        return at + "mode_posterior";
      }
    }
    if (g.flags != w.flags) return at + "flags";
    if (g.mode_count != w.mode_count) return at + "mode_count";
    if (g.most_probable_mode != w.most_probable_mode) return at + "most_probable_mode";
  }
  return "";
}

// Read-write access to every byte of an existing shm object, whoever created it.
class RawShm {
 public:
  explicit RawShm(const std::string& name) {
    const int fd = ::shm_open(name.c_str(), O_RDWR, 0);
    if (fd < 0) throw std::runtime_error("RawShm: cannot open " + name);
    struct stat st {};
    ::fstat(fd, &st);
    size_ = static_cast<std::size_t>(st.st_size);
    void* p = ::mmap(nullptr, size_, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    ::close(fd);
    if (p == MAP_FAILED) throw std::runtime_error("RawShm: cannot map " + name);
    base_ = static_cast<unsigned char*>(p);
  }
  ~RawShm() { ::munmap(base_, size_); }
  RawShm(const RawShm&) = delete;
  RawShm& operator=(const RawShm&) = delete;

  template <class T>
  T get(std::size_t offset) const {
    T value;
    std::memcpy(&value, base_ + offset, sizeof value);
    return value;
  }
  template <class T>
  void put(std::size_t offset, T value) {
    std::memcpy(base_ + offset, &value, sizeof value);
  }
  const unsigned char* bytes() const { return base_; }
  std::size_t size() const { return size_; }

 private:
  unsigned char* base_ = nullptr;
  std::size_t size_ = 0;
};

// Creates an shm object of `bytes` bytes that starts with `content` (the rest zero).
inline void create_raw_object(const std::string& name, std::size_t bytes,
                              const std::string& content) {
  const int fd = ::shm_open(name.c_str(), O_CREAT | O_EXCL | O_RDWR, 0600);
  if (fd < 0) throw std::runtime_error("create_raw_object: cannot create " + name);
  if (::ftruncate(fd, static_cast<off_t>(bytes)) != 0 ||
      ::write(fd, content.data(), content.size()) != static_cast<ssize_t>(content.size())) {
    ::close(fd);
    throw std::runtime_error("create_raw_object: cannot fill " + name);
  }
  ::close(fd);
}

// Runs `child` in a forked process (as user `uid` when given) and returns its exit status.
template <class Child>
int run_in_child(Child child, std::optional<uid_t> uid = std::nullopt) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    if (uid && (::setgid(*uid) != 0 || ::setuid(*uid) != 0)) ::_exit(100);
    ::_exit(child());
  }
  int status = 0;
  if (pid < 0 || ::waitpid(pid, &status, 0) != pid || !WIFEXITED(status)) return -1;
  return WEXITSTATUS(status);
}

}  // namespace tofcomp::ipc::ring::testing
