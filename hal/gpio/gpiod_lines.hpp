// The GPIO seam on libgpiod v1 (the character device /dev/gpiochipN): an output line and an
// input line with edge events, requested as consumer "tofcompd" and released on destruction.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "hal/gpio/gpio_line.hpp"

struct gpiod_chip;
struct gpiod_line;

namespace tofcomp::hal {

// The name under which tofcomp requests its lines (shown by gpioinfo).
inline constexpr const char* kGpioConsumer = "tofcompd";

// An open chip and one of its lines; releases the line and closes the chip on destruction.
// `chip` is anything gpiod_chip_open_lookup takes: "gpiochip0", "0", "/dev/gpiochip0" or the
// chip's label; `line` is the line's offset (all digits) or its name ("SCANNER_PWR").
class GpiodLine {
 public:
  // Throws GpioError naming the chip, the line and the errno when either cannot be found.
  GpiodLine(const std::string& chip, const std::string& line);
  ~GpiodLine();
  GpiodLine(const GpiodLine&) = delete;
  GpiodLine& operator=(const GpiodLine&) = delete;

  gpiod_line* line() const { return line_; }
  // "gpiochip0 line 17" as given in the configuration.
  const std::string& describe() const { return description_; }
  // Throws GpioError with `what`, this line and the errno `error`.
  [[noreturn]] void fail(const std::string& what, int error) const;

 private:
  std::string description_;
  gpiod_chip* chip_ = nullptr;
  gpiod_line* line_ = nullptr;
};

class GpiodOutput : public GpioOutput {
 public:
  // Requests the line as an output driven to `initially_active`; active_low inverts the
  // logical value at the pin (GPIOD_LINE_REQUEST_FLAG_ACTIVE_LOW). Throws GpioError.
  GpiodOutput(const std::string& chip, const std::string& line, bool active_low,
              bool initially_active);

  void set(bool active) override;
  bool get() const override;
  std::string describe() const override { return line_.describe(); }

 private:
  GpiodLine line_;
};

class GpiodEdgeSource : public GpioEdgeSource {
 public:
  // Requests the line as an input with events on both edges; active_low as for GpiodOutput.
  // The event descriptor is made non-blocking. Throws GpioError.
  GpiodEdgeSource(const std::string& chip, const std::string& line, bool active_low);

  int event_fd() const override { return fd_; }
  std::vector<GpioEdge> read_edges() override;
  bool level() const override;
  std::string describe() const override { return line_.describe(); }

 private:
  GpiodLine line_;
  int fd_ = -1;
};

}  // namespace tofcomp::hal
