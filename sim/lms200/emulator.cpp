#include "sim/lms200/emulator.hpp"

#include "sim/lms200/pty_link.hpp"
#include "sim/lms200/recording_scan_source.hpp"
#include "sim/lms200/twin_scan_source.hpp"

namespace tofcomp::sim::lms200 {

namespace {
// The scan source the settings ask for: the recording's playback when they hold one (the
// scenario still checked), else the twin.
std::unique_ptr<ScanSource> source_of(EmulatorSettings& settings) {
  if (!settings.recording) {
    return std::make_unique<TwinScanSource>(settings.scenario, settings.time_scale);
  }
  settings.scenario.validate();
  auto source =
      std::make_unique<RecordingScanSource>(*settings.recording, settings.recording_source,
                                            settings.time_scale, settings.hold_recorded_scans);
  settings.recording.reset();  // the source holds what it plays
  return source;
}
}  // namespace

Emulator::Emulator(EmulatorSettings settings) {
  std::unique_ptr<ScanSource> source = source_of(settings);
  recording_ = dynamic_cast<RecordingScanSource*>(source.get());
  link_ = std::make_unique<PtyLink>(std::move(settings), std::move(source));
}
Emulator::~Emulator() = default;
void Emulator::on_scan_sent(ScanObserver observer) {
  link_->scan_observer = std::move(observer);
}
void Emulator::on_fault(FaultObserver observer) {
  link_->fault_observer = std::move(observer);
}
void Emulator::on_playback_event(PlaybackObserver observer) {
  if (recording_) recording_->on_playback_event(std::move(observer));
}
void Emulator::start() {
  link_->start();
}
void Emulator::stop() {
  link_->stop();
}
std::string Emulator::device_path() const {
  return link_->device_path();
}
EmulatorCounters Emulator::counters() const {
  return link_->counters();
}
double Emulator::read_case_sensor() {
  return link_->read_case_sensor();
}
double Emulator::twin_time_s() const {
  return link_->source_time_s();
}
bool Emulator::power_on() const {
  return link_->power_on();
}
void Emulator::set_power(bool on) {
  link_->set_power(on);
}

}  // namespace tofcomp::sim::lms200
