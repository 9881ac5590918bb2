// tofcomp-ros2-bridge end to end: tofcompd on its emulated LMS 200 (a private socket and ring),
// the bridge as a process of its own, and in this process a DDS subscriber with the same
// generated types on the topics a ROS 2 node would read ("rt/scan", "rt/diagnostics"), on a
// domain of this run's own and on loopback only. Each LaserScan sample is checked against the
// socket's JSON answer for the same scan (matched by the first ray's time), each
// DiagnosticArray against `status` and the scans it covers.
#include <dds/dds.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <thread>

#include "bridges/ros2/ros2_interfaces.h"
#include "tests/daemon/e2e/daemon_process.hpp"
#include "tests/daemon/e2e/e2e_config.hpp"
#include "tofcomp/client.hpp"

namespace tofcomp::test {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

constexpr auto kDeadline = 90s;  // generous: the machine is shared
constexpr std::size_t kScansToCheck = 25;
constexpr std::size_t kReportsToCheck = 3;
constexpr double kTurnNs = 1e9 / 75.0;

// Cyclone DDS on loopback alone, discovering peers by unicast (lo has no multicast).
constexpr const char* kLoopbackDds =
    "<CycloneDDS><Domain><General><Interfaces><NetworkInterface name=\"lo\"/></Interfaces>"
    "<AllowMulticast>false</AllowMulticast></General><Discovery><Peers><Peer address=\"127.0.0.1\"/>"
    "</Peers><ParticipantIndex>auto</ParticipantIndex></Discovery></Domain></CycloneDDS>";

// The bridge as a child process on `config`, its output to `log`.
class BridgeProcess : public ChildProcess {
 public:
  BridgeProcess(const std::filesystem::path& config, const std::filesystem::path& log)
      : ChildProcess(TOFCOMP_ROS2_BRIDGE_BINARY, {"--config", config.string()}, log) {}
};

// A DDS reader of `type` on `topic` with ROS 2's QoS of that topic's publisher.
dds_entity_t reader_for(dds_entity_t participant, const dds_topic_descriptor_t* type,
                        const char* topic, dds_reliability_kind_t reliability) {
  const dds_entity_t t = dds_create_topic(participant, type, topic, nullptr, nullptr);
  EXPECT_GT(t, 0) << dds_strretcode(-t);
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, reliability, DDS_MSECS(100));
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 200);
  const dds_entity_t reader = dds_create_reader(participant, t, qos, nullptr);
  dds_delete_qos(qos);
  EXPECT_GT(reader, 0) << dds_strretcode(-reader);
  return reader;
}

// Takes the samples of a reader one at a time into memory of its own (no loans).
template <typename Sample>
class SampleTaker {
 public:
  SampleTaker(dds_entity_t reader, const dds_topic_descriptor_t* type) : reader_(reader), type_(type) {}
  ~SampleTaker() { dds_sample_free(&sample_, type_, DDS_FREE_CONTENTS); }
  SampleTaker(const SampleTaker&) = delete;
  SampleTaker& operator=(const SampleTaker&) = delete;

  // The next sample with data, valid until the next take; nullptr when none is waiting.
  const Sample* take() {
    dds_sample_free(&sample_, type_, DDS_FREE_CONTENTS);
    sample_ = Sample{};
    void* buffer = &sample_;
    dds_sample_info_t info{};
    return dds_take(reader_, &buffer, &info, 1, 1) == 1 && info.valid_data ? &sample_ : nullptr;
  }

 private:
  dds_entity_t reader_;
  const dds_topic_descriptor_t* type_;
  Sample sample_{};
};

// The socket's scans, by sequence and by their first ray's time.
class SocketScans {
 public:
  explicit SocketScans(client::Connection& daemon) : daemon_(daemon) {}
  void read(std::chrono::milliseconds timeout) {
    if (std::optional<client::Scan> scan = daemon_.next_scan(timeout)) {
      scan->json.clear();
      sequence_of_stamp_[scan->info.first_ray_ns] = scan->info.sequence;
      by_sequence_[scan->info.sequence] = std::move(*scan);
    }
  }
  bool empty() const { return by_sequence_.empty(); }
  std::int64_t first_stamp() const { return sequence_of_stamp_.begin()->first; }
  std::uint64_t first_sequence() const { return by_sequence_.begin()->first; }
  const client::Scan* with_stamp(std::int64_t stamp) const {
    const auto found = sequence_of_stamp_.find(stamp);
    return found == sequence_of_stamp_.end() ? nullptr : &by_sequence_.at(found->second);
  }
  const client::Scan* with_sequence(std::uint64_t sequence) const {
    const auto found = by_sequence_.find(sequence);
    return found == by_sequence_.end() ? nullptr : &found->second;
  }

 private:
  client::Connection& daemon_;
  std::map<std::int64_t, std::uint64_t> sequence_of_stamp_;
  std::map<std::uint64_t, client::Scan> by_sequence_;
};

std::int64_t stamp_ns(const builtin_interfaces_msg_dds__Time_& t) {
  return static_cast<std::int64_t>(t.sec_) * 1000000000 + t.nanosec_;
}

float radians(double degrees) { return static_cast<float>(degrees * std::numbers::pi / 180.0); }

// The range ROS should see for a beam, by REP 117, from the socket's JSON answer.
void expect_range(float published, const client::Beam& beam, std::size_t index) {
  if ((beam.flags & TOFCOMP_FLAG_NO_ECHO) != 0) {
    EXPECT_TRUE(std::isinf(published) && published > 0) << "beam " << index << ": " << published;
  } else if (std::isnan(beam.compensated_mm)) {
    EXPECT_TRUE(std::isnan(published)) << "beam " << index << ": " << published;
  } else {
    const float expected = static_cast<float>(beam.compensated_mm / 1000.0);
    // within two float steps: the bridge reads the compact frame's float32 millimetres
    EXPECT_NEAR(published, expected, 2.5e-7f * std::fabs(expected)) << "beam " << index;
  }
}

// One LaserScan sample against the same scan as the socket sent it in JSON.
void expect_same_scan(const sensor_msgs_msg_dds__LaserScan_& sample, const client::Scan& scan) {
  const client::ScanInfo& info = scan.info;
  EXPECT_STREQ(sample.header_.frame_id_, "test_laser");
  EXPECT_EQ(stamp_ns(sample.header_.stamp_), info.first_ray_ns);
  ASSERT_EQ(sample.ranges_._length, info.beam_count);
  EXPECT_EQ(sample.intensities_._length, 0u);
  EXPECT_FLOAT_EQ(sample.angle_min_, radians(info.start_angle_deg - 90.0));
  EXPECT_FLOAT_EQ(sample.angle_max_,
                  radians(info.start_angle_deg + (info.beam_count - 1) * info.resolution_deg - 90.0));
  EXPECT_FLOAT_EQ(sample.angle_increment_, radians(info.resolution_deg));
  EXPECT_FLOAT_EQ(sample.range_max_, 81.91f);
  EXPECT_EQ(sample.range_min_, 0.0f);
  // docs/protocol.md "Time": the last ray is that of the last beam L of turn n − 1, (n − 1)
  // turns and ⌊L / n⌋ ray intervals after the first; the LMS 200's mirror turns at 75 Hz.
  const std::uint32_t n = info.interlaced_turns;
  ASSERT_GT(n, 0u);
  EXPECT_NEAR(info.turn_period_ns, kTurnNs, 1.0);
  std::uint32_t last = info.beam_count - 1;
  while (last % n != n - 1) --last;
  const double sweep_ns = (n - 1) * info.turn_period_ns + (last / n) * info.ray_interval_ns;
  EXPECT_FLOAT_EQ(sample.time_increment_,
                  static_cast<float>(sweep_ns / (info.beam_count - 1) / 1e9));
  EXPECT_FLOAT_EQ(sample.scan_time_, static_cast<float>(n * info.turn_period_ns / 1e9));
  for (std::size_t i = 0; i < info.beam_count; ++i) {
    expect_range(sample.ranges_._buffer[i], scan.beams[i], i);
  }
}

// A sample as `ros2 topic echo` lays it out (docs/integration.md shows this output), the ranges
// around beam `middle` only.
void print_sample(const sensor_msgs_msg_dds__LaserScan_& s, std::size_t middle) {
  std::cout << "header:\n  stamp:\n    sec: " << s.header_.stamp_.sec_
            << "\n    nanosec: " << s.header_.stamp_.nanosec_ << "\n  frame_id: "
            << s.header_.frame_id_ << "\nangle_min: " << s.angle_min_
            << "\nangle_max: " << s.angle_max_ << "\nangle_increment: " << s.angle_increment_
            << "\ntime_increment: " << s.time_increment_ << "\nscan_time: " << s.scan_time_
            << "\nrange_min: " << s.range_min_ << "\nrange_max: " << s.range_max_
            << "\nranges (" << s.ranges_._length << "), beams " << middle - 2 << ".." << middle + 2
            << ":\n";
  for (std::size_t i = middle - 2; i <= middle + 2; ++i) std::cout << "- " << s.ranges_._buffer[i] << "\n";
  std::cout << "intensities: []\n---" << std::endl;
}

// A report's status as `ros2 topic echo /diagnostics` lays it out.
void print_report(const diagnostic_msgs_msg_dds__DiagnosticStatus_& status) {
  std::cout << "status:\n- level: " << int{status.level_} << "\n  name: " << status.name_
            << "\n  message: " << status.message_ << "\n  hardware_id: " << status.hardware_id_
            << "\n  values:\n";
  for (std::uint32_t i = 0; i < status.values_._length; ++i) {
    std::cout << "  - key: " << status.values_._buffer[i].key_
              << "\n    value: " << status.values_._buffer[i].value_ << "\n";
  }
  std::cout << "---" << std::endl;
}

std::map<std::string, std::string> values_of(const diagnostic_msgs_msg_dds__DiagnosticStatus_& s) {
  std::map<std::string, std::string> values;
  for (std::uint32_t i = 0; i < s.values_._length; ++i) {
    values[s.values_._buffer[i].key_] = s.values_._buffer[i].value_;
  }
  return values;
}

class Ros2Bridge : public ::testing::Test {
 protected:
  void SetUp() override {
    domain_ = 1 + static_cast<std::uint32_t>(::getpid() % 200);  // this run's own
    ::setenv("CYCLONEDDS_URI", kLoopbackDds, 1);                  // the bridge inherits it
    shm_ = "/tofcomp-ros2-test-" + std::to_string(::getpid());
    const auto config = dir_.path() / "tofcompd.yaml";
    write_file(config, config_text(dir_.path(), shm_,
                                   std::string(TOFCOMP_SOURCE_ROOT) + "/config/calibration.yaml"));
    daemon_ = std::make_unique<DaemonProcess>(config, dir_.path() / "tofcompd.log");
    ASSERT_TRUE(wait_for_socket(socket(), 30s)) << daemon_->log();
  }

  std::string socket() const { return (dir_.path() / "tofcompd.sock").string(); }

  std::filesystem::path bridge_config(bool enabled) const {
    const auto path = dir_.path() / "bridge.yaml";
    write_file(path, "ros2:\n  enabled: " + std::string(enabled ? "true" : "false") +
                         "\n  domain_id: " + std::to_string(domain_) +
                         "\n  frame_id: test_laser\n  socket: " + socket() +
                         "\n  diagnostics_period_s: 0.5\n");
    return path;
  }
  std::string logs() const {
    return "bridge:\n" + (bridge_ ? bridge_->log() : "") + "\ndaemon:\n" + daemon_->log();
  }

  TemporaryDirectory dir_;
  std::string shm_;
  std::uint32_t domain_ = 0;
  std::unique_ptr<DaemonProcess> daemon_;
  std::unique_ptr<BridgeProcess> bridge_;
};

TEST_F(Ros2Bridge, ScansAndHealthReachADdsSubscriberAsTheSocketAnswers) {
  const dds_entity_t participant = dds_create_participant(domain_, nullptr, nullptr);
  ASSERT_GT(participant, 0) << dds_strretcode(-participant);
  const dds_entity_t scans = reader_for(participant, &sensor_msgs_msg_dds__LaserScan__desc,
                                        "rt/scan", DDS_RELIABILITY_BEST_EFFORT);
  const dds_entity_t reports = reader_for(participant, &diagnostic_msgs_msg_dds__DiagnosticArray__desc,
                                          "rt/diagnostics", DDS_RELIABILITY_RELIABLE);
  // The socket's answer: every scan as JSON, from before the bridge starts.
  client::Connection daemon(socket(), 30s);
  daemon.subscribe(std::nullopt, 1, client::Format::Json, 30s);
  client::Connection control(socket(), 30s);
  bridge_ = std::make_unique<BridgeProcess>(bridge_config(true), dir_.path() / "bridge.log");

  SocketScans socket_scans(daemon);
  SampleTaker<sensor_msgs_msg_dds__LaserScan_> scan_samples(scans, &sensor_msgs_msg_dds__LaserScan__desc);
  SampleTaker<diagnostic_msgs_msg_dds__DiagnosticArray_> report_samples(
      reports, &diagnostic_msgs_msg_dds__DiagnosticArray__desc);
  std::size_t scans_checked = 0;
  std::size_t reports_checked = 0;
  const auto until = Clock::now() + kDeadline;
  while ((scans_checked < kScansToCheck || reports_checked < kReportsToCheck) &&
         Clock::now() < until && !HasFailure()) {
    socket_scans.read(20ms);
    // A scan from before this test's subscription cannot be matched; any later one must be.
    const auto* sample = scan_samples.take();
    if (sample && !socket_scans.empty() &&
        stamp_ns(sample->header_.stamp_) >= socket_scans.first_stamp()) {
      const std::int64_t stamp = stamp_ns(sample->header_.stamp_);
      // the socket's copy may come a little after the DDS one
      const auto wait_until = Clock::now() + 10s;
      while (!socket_scans.with_stamp(stamp) && Clock::now() < wait_until) socket_scans.read(100ms);
      const client::Scan* scan = socket_scans.with_stamp(stamp);
      ASSERT_NE(scan, nullptr) << "no scan of the socket has the stamp " << stamp << "\n" << logs();
      expect_same_scan(*sample, *scan);
      if (scans_checked++ == 0) print_sample(*sample, sample->ranges_._length / 2);
    }
    const auto* report = report_samples.take();
    if (!report) continue;
    ASSERT_EQ(report->status_._length, 1u);
    const auto& status = report->status_._buffer[0];
    auto values = values_of(status);
    EXPECT_EQ(std::string(status.name_), "tofcompd: " + socket());
    // A report covers the scans since the previous one: check those wholly after the
    // subscription's first scan.
    if (values["scans"] == "0" || socket_scans.empty() ||
        std::stoull(values["first scan"]) <= socket_scans.first_sequence()) {
      continue;
    }
    const nlohmann::json now =
        nlohmann::json::parse(control.call(R"({"op":"status"})", 30s)).at("status");
    EXPECT_EQ(values["calibration id"], std::to_string(now["calibration"]["id"].get<int>()));
    EXPECT_EQ(values["calibration extension"], "none");
    EXPECT_EQ(values["link"], now["link"].get<std::string>());
    EXPECT_EQ(values["state"], now["state"].get<std::string>());
    EXPECT_EQ(std::string(status.hardware_id_), now["device"].get<std::string>());
    EXPECT_LE(status.level_, diagnostic_msgs_msg_dds__DiagnosticStatus_Constants_WARN_);
    // The latest scan's junction temperature, exactly as the socket sent it.
    const client::Scan* latest = socket_scans.with_sequence(std::stoull(values["scan"]));
    ASSERT_NE(latest, nullptr) << values["scan"];
    EXPECT_EQ(std::stod(values["junction temperature (°C)"]), latest->info.junction_c);
    EXPECT_EQ(std::stod(values["junction temperature std (°C)"]), latest->info.junction_std_c);
    EXPECT_GT(stamp_ns(report->header_.stamp_), latest->info.first_ray_ns);
    // The flagged beams of the scans covered, counted here from the JSON flags.
    const std::uint16_t range_flags = TOFCOMP_FLAG_UNCALIBRATED | TOFCOMP_FLAG_TEMPERATURE_STALE |
                                      TOFCOMP_FLAG_OUTLIER | TOFCOMP_FLAG_TEMPERATURE_EXTRAPOLATED;
    std::uint64_t beams = 0, flagged = 0, no_echo = 0, covered = 0;
    for (auto s = std::stoull(values["first scan"]); s <= std::stoull(values["last scan"]); ++s) {
      const client::Scan* scan = socket_scans.with_sequence(s);
      ASSERT_NE(scan, nullptr) << "scan " << s;
      ++covered;
      for (const client::Beam& beam : scan->beams) {
        ++beams;
        if ((beam.flags & range_flags) != 0) ++flagged;
        if ((beam.flags & TOFCOMP_FLAG_NO_ECHO) != 0) ++no_echo;
      }
    }
    EXPECT_EQ(values["scans"], std::to_string(covered));
    EXPECT_EQ(values["beams"], std::to_string(beams));
    EXPECT_EQ(values["flagged beams"], std::to_string(flagged));
    EXPECT_EQ(values["beams without echo"], std::to_string(no_echo));
    EXPECT_DOUBLE_EQ(std::stod(values["flagged beams (share)"]),
                     static_cast<double>(flagged) / static_cast<double>(beams));
    if (reports_checked++ == 0) print_report(status);
  }
  EXPECT_GE(scans_checked, kScansToCheck) << logs();
  EXPECT_GE(reports_checked, kReportsToCheck) << logs();
  EXPECT_EQ(bridge_->terminate(20s), 0) << logs();
  dds_delete(participant);
}

TEST_F(Ros2Bridge, ADisabledBridgeExitsAtOnceSayingWhy) {
  bridge_ = std::make_unique<BridgeProcess>(bridge_config(false), dir_.path() / "bridge.log");
  EXPECT_EQ(bridge_->wait_exit(30s), 0) << logs();
  EXPECT_NE(bridge_->log().find("ros2.enabled: false"), std::string::npos) << logs();
}

}  // namespace
}  // namespace tofcomp::test
