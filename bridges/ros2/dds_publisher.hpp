// The bridge's DDS side (Cyclone DDS's C API): a participant on the configured domain and two
// writers with the topic names, type names and QoS a ROS 2 node's publishers would have
// (rmw_cyclonedds: topic "rt" + the ROS name, type "<package>::msg::dds_::<Message>_"):
// LaserScan with the sensor-data profile (best effort, keep last 5, volatile), DiagnosticArray
// with the default profile (reliable, keep last 10, volatile). docs/integration.md, "ROS 2".
#pragma once

#include <dds/dds.h>

#include <cstdint>
#include <string>

#include "bridges/ros2/laser_scan.hpp"
#include "bridges/ros2/scanner_diagnostics.hpp"

namespace tofcomp::bridges::ros2 {

// ROS 2's QoS profiles as rmw/qos_profiles.h defines them.
inline constexpr int32_t kSensorDataDepth = 5;
inline constexpr int32_t kDefaultProfileDepth = 10;
// How long a reliable write may wait for room in a slow reader's history.
inline constexpr dds_duration_t kMaxBlockingTime = DDS_MSECS(100);

// A ROS 2 time (builtin_interfaces/Time) from ns since the epoch: whole seconds (floor) and
// 0..999,999,999 ns.
struct RosTime {
  std::int32_t sec = 0;
  std::uint32_t nanosec = 0;
};
RosTime ros_time(std::int64_t ns);

class DdsPublisher {
 public:
  // Throws core::Error naming the DDS call and its return code (e.g. a CYCLONEDDS_URI that
  // does not parse).
  DdsPublisher(std::uint32_t domain_id, const std::string& scan_topic,
               const std::string& diagnostics_topic);
  ~DdsPublisher();
  DdsPublisher(const DdsPublisher&) = delete;
  DdsPublisher& operator=(const DdsPublisher&) = delete;

  void publish_scan(const LaserScanValues& scan, const std::string& frame_id);
  void publish_diagnostics(std::int64_t stamp_ns, const DiagnosticValues& status);

 private:
  dds_entity_t participant_ = 0;
  dds_entity_t scan_writer_ = 0;
  dds_entity_t diagnostics_writer_ = 0;
};

}  // namespace tofcomp::bridges::ros2
