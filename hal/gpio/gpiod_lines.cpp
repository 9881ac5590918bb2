#include "hal/gpio/gpiod_lines.hpp"

#include <fcntl.h>
#include <gpiod.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <system_error>

namespace tofcomp::hal {
namespace {

std::string errno_text(int error) {
  return error == 0 ? "unknown error" : std::error_code(error, std::generic_category()).message();
}

bool is_offset(const std::string& line) {
  return !line.empty() && line.size() < 10 &&
         std::all_of(line.begin(), line.end(), [](char c) { return c >= '0' && c <= '9'; });
}

int request_flags(bool active_low) {
  return active_low ? GPIOD_LINE_REQUEST_FLAG_ACTIVE_LOW : 0;
}

}  // namespace

GpiodLine::GpiodLine(const std::string& chip, const std::string& line)
    : description_("gpio chip '" + chip + "' line '" + line + "'") {
  if (chip.empty()) throw GpioError("gpio: empty chip name (for line '" + line + "')", EINVAL);
  if (line.empty()) throw GpioError("gpio chip '" + chip + "': empty line name or offset", EINVAL);
  errno = 0;
  chip_ = ::gpiod_chip_open_lookup(chip.c_str());
  if (chip_ == nullptr) {
    const int error = errno;
    throw GpioError(
        "gpio chip '" + chip + "': cannot open (line '" + line + "'): " + errno_text(error), error);
  }
  errno = 0;
  line_ = is_offset(line) ? ::gpiod_chip_get_line(chip_, static_cast<unsigned>(std::stoul(line)))
                          : ::gpiod_chip_find_line(chip_, line.c_str());
  if (line_ == nullptr) {
    const int error = errno;
    const std::string lines = std::to_string(::gpiod_chip_num_lines(chip_));
    ::gpiod_chip_close(chip_);
    throw GpioError(description_ + ": no such line on the chip (it has " + lines +
                        " lines): " + errno_text(error),
                    error);
  }
}

GpiodLine::~GpiodLine() {
  if (line_ != nullptr && ::gpiod_line_is_requested(line_)) ::gpiod_line_release(line_);
  if (chip_ != nullptr) ::gpiod_chip_close(chip_);
}

void GpiodLine::fail(const std::string& what, int error) const {
  std::string message = description_ + ": " + what + ": " + errno_text(error);
  if (error == EBUSY && line_ != nullptr) {
    const char* consumer = ::gpiod_line_consumer(line_);
    if (consumer != nullptr) message += " (in use by '" + std::string(consumer) + "')";
  }
  throw GpioError(message, error);
}

GpiodOutput::GpiodOutput(const std::string& chip, const std::string& line, bool active_low,
                         bool initially_active)
    : line_(chip, line) {
  if (::gpiod_line_request_output_flags(line_.line(), kGpioConsumer, request_flags(active_low),
                                        initially_active ? 1 : 0) < 0)
    line_.fail("cannot request as output", errno);
}

void GpiodOutput::set(bool active) {
  if (::gpiod_line_set_value(line_.line(), active ? 1 : 0) < 0)
    line_.fail(std::string("cannot set ") + (active ? "active" : "inactive"), errno);
}

bool GpiodOutput::get() const {
  const int value = ::gpiod_line_get_value(line_.line());
  if (value < 0) line_.fail("cannot read the value", errno);
  return value == 1;
}

GpiodEdgeSource::GpiodEdgeSource(const std::string& chip, const std::string& line, bool active_low)
    : line_(chip, line) {
  if (::gpiod_line_request_both_edges_events_flags(line_.line(), kGpioConsumer,
                                                   request_flags(active_low)) < 0)
    line_.fail("cannot request edge events", errno);
  fd_ = ::gpiod_line_event_get_fd(line_.line());
  if (fd_ < 0) line_.fail("no event descriptor", errno);
  const int flags = ::fcntl(fd_, F_GETFL);
  if (flags < 0 || ::fcntl(fd_, F_SETFL, flags | O_NONBLOCK) < 0)
    line_.fail("cannot make the event descriptor non-blocking", errno);
}

std::vector<GpioEdge> GpiodEdgeSource::read_edges() {
  std::vector<GpioEdge> edges;
  std::array<gpiod_line_event, 16> events{};
  for (;;) {
    const int n = ::gpiod_line_event_read_multiple(line_.line(), events.data(),
                                                   static_cast<unsigned>(events.size()));
    if (n < 0) {
      if (errno == EAGAIN || errno == EWOULDBLOCK) break;
      if (errno == EINTR) continue;
      line_.fail("cannot read edge events", errno);
    }
    for (int i = 0; i < n; ++i) {
      const auto& event = events[static_cast<std::size_t>(i)];
      edges.push_back(GpioEdge{
          event.event_type == GPIOD_LINE_EVENT_RISING_EDGE,
          std::chrono::seconds(event.ts.tv_sec) + std::chrono::nanoseconds(event.ts.tv_nsec)});
    }
    if (n < static_cast<int>(events.size())) break;
  }
  return edges;
}

bool GpiodEdgeSource::level() const {
  const int value = ::gpiod_line_get_value(line_.line());
  if (value < 0) line_.fail("cannot read the value", errno);
  return value == 1;
}

}  // namespace tofcomp::hal
