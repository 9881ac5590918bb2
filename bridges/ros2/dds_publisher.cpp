#include "bridges/ros2/dds_publisher.hpp"

#include <memory>
#include <vector>

#include "bridges/ros2/bridge_config.hpp"
#include "bridges/ros2/ros2_interfaces.h"
#include "core/error.hpp"
#include "core/ray_timing.hpp"

namespace tofcomp::bridges::ros2 {

namespace {

// A DDS return code below 0 is an error: throws naming the call.
dds_entity_t checked(dds_entity_t result, const std::string& what) {
  if (result < 0) {
    throw core::Error("DDS: " + what + " failed: " + dds_strretcode(-result));
  }
  return result;
}

using QosPtr = std::unique_ptr<dds_qos_t, decltype(&dds_delete_qos)>;

QosPtr ros_qos(dds_reliability_kind_t reliability, int32_t depth) {
  QosPtr qos(dds_create_qos(), &dds_delete_qos);
  dds_qset_reliability(qos.get(), reliability, kMaxBlockingTime);
  dds_qset_history(qos.get(), DDS_HISTORY_KEEP_LAST, depth);
  dds_qset_durability(qos.get(), DDS_DURABILITY_VOLATILE);
  return qos;
}

dds_entity_t writer_for(dds_entity_t participant, const dds_topic_descriptor_t* type,
                        const std::string& ros_topic, const dds_qos_t* qos) {
  const std::string name = dds_topic_name(ros_topic);
  const dds_entity_t topic =
      checked(dds_create_topic(participant, type, name.c_str(), nullptr, nullptr),
              "creating topic " + name);
  return checked(dds_create_writer(participant, topic, qos, nullptr), "creating a writer of " + name);
}

char* text(const std::string& s) { return const_cast<char*>(s.c_str()); }

std_msgs_msg_dds__Header_ header(std::int64_t stamp_ns, const std::string& frame_id) {
  const RosTime t = ros_time(stamp_ns);
  std_msgs_msg_dds__Header_ h{};
  h.stamp_.sec_ = t.sec;
  h.stamp_.nanosec_ = t.nanosec;
  h.frame_id_ = text(frame_id);
  return h;
}

}  // namespace

RosTime ros_time(std::int64_t ns) {
  std::int64_t sec = ns / core::kNsPerSecond;
  std::int64_t rest = ns % core::kNsPerSecond;
  if (rest < 0) {
    rest += core::kNsPerSecond;
    --sec;
  }
  return RosTime{static_cast<std::int32_t>(sec), static_cast<std::uint32_t>(rest)};
}

DdsPublisher::DdsPublisher(std::uint32_t domain_id, const std::string& scan_topic,
                           const std::string& diagnostics_topic) {
  participant_ = checked(dds_create_participant(domain_id, nullptr, nullptr),
                         "creating a participant on domain " + std::to_string(domain_id));
  try {
    const QosPtr sensor_data = ros_qos(DDS_RELIABILITY_BEST_EFFORT, kSensorDataDepth);
    const QosPtr default_profile = ros_qos(DDS_RELIABILITY_RELIABLE, kDefaultProfileDepth);
    scan_writer_ = writer_for(participant_, &sensor_msgs_msg_dds__LaserScan__desc, scan_topic,
                              sensor_data.get());
    diagnostics_writer_ = writer_for(participant_, &diagnostic_msgs_msg_dds__DiagnosticArray__desc,
                                     diagnostics_topic, default_profile.get());
  } catch (...) {
    dds_delete(participant_);
    throw;
  }
}

DdsPublisher::~DdsPublisher() { dds_delete(participant_); }

void DdsPublisher::publish_scan(const LaserScanValues& scan, const std::string& frame_id) {
  sensor_msgs_msg_dds__LaserScan_ sample{};
  sample.header_ = header(scan.stamp_ns, frame_id);
  sample.angle_min_ = scan.angle_min;
  sample.angle_max_ = scan.angle_max;
  sample.angle_increment_ = scan.angle_increment;
  sample.time_increment_ = scan.time_increment;
  sample.scan_time_ = scan.scan_time;
  sample.range_min_ = scan.range_min;
  sample.range_max_ = scan.range_max;
  // The sample borrows the vector's storage: dds_write serializes it before returning.
  sample.ranges_._length = sample.ranges_._maximum = static_cast<uint32_t>(scan.ranges.size());
  sample.ranges_._buffer = const_cast<float*>(scan.ranges.data());
  sample.ranges_._release = false;
  checked(dds_write(scan_writer_, &sample), "writing a LaserScan");
}

void DdsPublisher::publish_diagnostics(std::int64_t stamp_ns, const DiagnosticValues& status) {
  std::vector<diagnostic_msgs_msg_dds__KeyValue_> values;
  values.reserve(status.values.size());
  for (const auto& [key, value] : status.values) values.push_back({text(key), text(value)});
  diagnostic_msgs_msg_dds__DiagnosticStatus_ entry{};
  entry.level_ = static_cast<uint8_t>(status.level);
  entry.name_ = text(status.name);
  entry.message_ = text(status.message);
  entry.hardware_id_ = text(status.hardware_id);
  entry.values_._length = entry.values_._maximum = static_cast<uint32_t>(values.size());
  entry.values_._buffer = values.data();
  entry.values_._release = false;

  const std::string no_frame;  // diagnostics belong to no frame
  diagnostic_msgs_msg_dds__DiagnosticArray_ sample{};
  sample.header_ = header(stamp_ns, no_frame);
  sample.status_._length = sample.status_._maximum = 1;
  sample.status_._buffer = &entry;
  sample.status_._release = false;
  checked(dds_write(diagnostics_writer_, &sample), "writing a DiagnosticArray");
}

}  // namespace tofcomp::bridges::ros2
