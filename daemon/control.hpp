// The daemon's answers to its clients and operators (daemon/socket/request_handler.hpp,
// docs/protocol.md): status and statistics gathered from the modules, reloading the
// configuration (SIGHUP or the socket's reload), recalibration handed to the recalibration.
// Owns the last reload's outcome and the counts of reloads and refusals.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "daemon/case_sensor_input.hpp"
#include "daemon/compensation_inputs.hpp"
#include "daemon/event_clock.hpp"
#include "daemon/recalibration.hpp"
#include "daemon/recordings.hpp"
#include "daemon/running_config.hpp"
#include "daemon/scan_outputs.hpp"
#include "daemon/scanner_link.hpp"
#include "daemon/service_status.hpp"
#include "daemon/socket/request_handler.hpp"

namespace tofcomp::daemon {

class Control : public socket::SocketRequestHandler {
 public:
  // What it reports on and acts upon.
  struct Modules {
    RunningConfig& config;
    const EventClock& clock;
    ServiceStatus& service;
    const ScannerLink& link;
    const CaseSensorInput& sensor;
    CompensationInputs& inputs;
    Recordings& recordings;
    const ScanOutputs& outputs;
    Recalibration& recalibration;
  };

  explicit Control(Modules modules) : modules_(modules) {}

  // SocketRequestHandler, on the loop.
  const ipc::CompensatedScan* latest_scan() override;
  nlohmann::json status() override;
  nlohmann::json stats() override;
  socket::ReloadResult reload() override;
  socket::RecalibrationResult recalibrate(const nlohmann::json& args) override;

 private:
  Modules modules_;
  std::string last_reload_ = "none";
  std::uint64_t reloads_ = 0;
  std::uint64_t reloads_refused_ = 0;
};

}  // namespace tofcomp::daemon
