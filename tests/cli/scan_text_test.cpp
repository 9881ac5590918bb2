// The one text form of a scan (cli/scan_text.hpp), against lines written out by hand: the
// header, the angle of each beam, "-" for what does not exist, the mode, the flag names.
#include "cli/scan_text.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace tofcomp::cli {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

ipc::CompensatedScan two_beam_scan() {
  ipc::CompensatedScan s;
  s.sequence = 50;
  s.device_sequence = 52;
  s.timestamp_ns = 1795430902471163255;  // 2026-11-23T10:48:22.471163255Z
  s.junction_c = 25.774;
  s.junction_std_c = 1.646;
  s.case_c = kNaN;
  s.start_angle_deg = 0.0;
  s.resolution_deg = 0.5;
  s.calibration_id = 1;
  s.beams.resize(361);
  ipc::BeamValue& wall = s.beams[180];
  wall.raw_mm = 3005.0;
  wall.compensated_mm = 3000.08;
  wall.window_mm = 3002.1;
  wall.window_std_mm = 0.209;
  wall.mode_count = 2;
  wall.most_probable_mode = 1;
  ipc::BeamValue& none = s.beams[181];
  none.raw_mm = 8183.0;
  none.compensated_mm = kNaN;
  none.window_mm = kNaN;
  none.window_std_mm = kNaN;
  none.flags = ipc::kBeamNoEcho | ipc::kBeamUncalibrated;
  return s;
}

TEST(ScanText, HeaderAndBeamsWrittenOutByHand) {
  EXPECT_EQ(scan_text(two_beam_scan(), {180, 2}),
            "scan 50 (device 52) at 2026-11-23T10:48:22.471Z; junction 25.77 ± 1.65 °C, case - "
            "°C; calibration 1; beams 180..181 of 361\n"
            " beam   angle°    raw mm   comp. mm  window mm   std mm  mode  flags\n"
            "  180    90.00    3005.0    3000.08    3002.10     0.21     1  -\n"
            "  181    90.50    8183.0          -          -        -     -  "
            "no_echo,uncalibrated\n");
}

TEST(ScanText, FirstRayShownBeforeTheArrivalWhenKnown) {
  ipc::CompensatedScan s = two_beam_scan();
  s.rays = {s.timestamp_ns - 34'603'704, 37037.0, 13333333.3, 2};
  EXPECT_NE(scan_text(s, {180, 1}).find("at 2026-11-23T10:48:22.471Z (first ray 34.6 ms before); "
                                        "junction"),
            std::string::npos);
}

TEST(ScanText, NoBeamsShown) {
  const std::string text = scan_text(two_beam_scan(), {361, 0});
  EXPECT_NE(text.find("; beams none of 361\n"), std::string::npos);
  EXPECT_EQ(text.substr(text.size() - 6), "flags\n");  // the table's header, no row
}

}  // namespace
}  // namespace tofcomp::cli
