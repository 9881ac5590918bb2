// The emulated LMS 200's scans drawn from the digital twin (sim/twin.hpp) in real time or
// faster: the twin advances one scan period at a time, paced by the wall clock scaled by
// time_scale (or as fast as the host reads at 0), powers the scanner off and on with the
// scenario's schedule, and draws each scan as the device is configured when the link sends it.
#pragma once

#include "sim/lms200/scan_source.hpp"
#include "sim/scenario.hpp"
#include "sim/twin.hpp"

namespace tofcomp::sim::lms200 {

class TwinScanSource : public ScanSource {
 public:
  // Throws core::InvalidInput for a bad scenario.
  TwinScanSource(const Scenario& scenario, double time_scale);

  bool power_on() const override;
  double read_case_sensor() override;
  double time_s() const override;
  void override_power(bool on) override;
  DrawnScan draw_scan(const Lms200Device& device) override;
  boost::asio::awaitable<void> stream(PtyLink& link) override;

 private:
  Scenario scenario_;
  Twin twin_;
  double time_scale_;

  // Advances the twin by one scan period; powers the device off and on with the schedule.
  void tick(PtyLink& link, double period_s);
};

}  // namespace tofcomp::sim::lms200
