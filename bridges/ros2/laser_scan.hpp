// A compensated scan of tofcompd as the fields of a ROS 2 sensor_msgs/msg/LaserScan (the DDS
// sample is filled from these by dds_publisher.cpp): ranges in metres with REP 117's special
// values, angles in the scanner's frame, the first ray's time. docs/integration.md, "ROS 2",
// says why each field is what it is.
#pragma once

#include <cstdint>
#include <vector>

#include "tofcomp/client.hpp"

namespace tofcomp::bridges::ros2 {

// The LMS 200's beam at 90° looks straight ahead: REP 103's x axis, angles counter-clockwise
// seen from above (the scanner mounted upright; another mounting is a transform in tf).
inline constexpr double kForwardAngleDeg = 90.0;

struct LaserScanValues {
  std::int64_t stamp_ns = 0;  // the first ray's time (the arrival when the rays' time is unknown)
  float angle_min = 0.0f;
  float angle_max = 0.0f;
  float angle_increment = 0.0f;
  float time_increment = 0.0f;
  float scan_time = 0.0f;
  float range_min = 0.0f;
  float range_max = 0.0f;
  std::vector<float> ranges;
};

// A beam's range for ROS (REP 117): the compensated range in metres; +Inf for no echo (nothing
// within the scanner's range); NaN when no compensated range exists (no calibration loaded).
float ros_range(const client::Beam& beam);

// The scan's LaserScan fields. Throws core::InvalidInput unless the scan carries every beam,
// 0 to beam_count − 1, at a resolution above 0.
LaserScanValues laser_scan_from(const client::Scan& scan);

}  // namespace tofcomp::bridges::ros2
