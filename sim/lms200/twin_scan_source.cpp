#include "sim/lms200/twin_scan_source.hpp"

#include <mutex>

#include "sim/lms200/pty_link.hpp"

namespace tofcomp::sim::lms200 {

using Clock = std::chrono::steady_clock;

TwinScanSource::TwinScanSource(const Scenario& scenario, double time_scale)
    : scenario_(scenario), twin_(scenario), time_scale_(time_scale) {}

bool TwinScanSource::power_on() const {
  return twin_.power_on();
}

double TwinScanSource::read_case_sensor() {
  return twin_.read_case_sensor();
}

double TwinScanSource::time_s() const {
  return twin_.time_s();
}

void TwinScanSource::override_power(bool on) {
  twin_.set_power_override(on);
}

DrawnScan TwinScanSource::draw_scan(const Lms200Device& device) {
  twin_.set_output(device.scanner_output(scenario_.scanner));
  std::vector<RangeReading> readings = twin_.scan();
  return {std::move(readings), twin_.time_s()};
}

void TwinScanSource::tick(PtyLink& link, double period_s) {
  bool on = false;
  {
    std::lock_guard lock(link.state_mutex());
    twin_.advance_to(twin_.time_s() + period_s);
    on = twin_.power_on();
  }
  link.switch_power(on);
}

boost::asio::awaitable<void> TwinScanSource::stream(PtyLink& link) {
  const Clock::time_point wall_start = Clock::now();
  const double twin_start = twin_.time_s();
  for (;;) {
    const double period_s =
        link.device().variant().turns_per_scan() / scenario_.scanner.scan_rate_hz;
    if (time_scale_ > 0.0) {
      const Clock::time_point due =
          wall_start + wall_duration((twin_.time_s() + period_s - twin_start) / time_scale_);
      co_await link.wait_for_host(due - Clock::now());
      if (Clock::now() < due) continue;  // woken early by a request; the tick is not due yet
      tick(link, period_s);
      if (!link.device().streaming() || !link.powered()) continue;
      if (link.idle()) {
        link.queue_scan();
      } else {
        link.count_skipped_scan();
      }
    } else {
      if (!link.powered()) {
        tick(link, period_s);
        continue;
      }
      // Nobody hears a line at the wrong rate: wait rather than race the twin ahead.
      if (!link.device().streaming() || !link.idle() || !link.rates_match()) {
        co_await link.wait_for_host(std::chrono::milliseconds(20));
        continue;
      }
      tick(link, period_s);
      if (link.powered() && link.device().streaming()) link.queue_scan();
    }
  }
}

}  // namespace tofcomp::sim::lms200
