// One published scan made into the event lines of every subscription: encoded once per distinct
// beam span, shared by every connection that takes that span.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "daemon/socket/request_dispatcher.hpp"
#include "ipc/compensated_scan.hpp"
#include "ipc/socket/scan_json.hpp"

namespace tofcomp::daemon::socket {

class ScanFanout {
 public:
  explicit ScanFanout(const ipc::CompensatedScan& scan) : scan_(scan) {}

  // The event line for a subscription; nullptr when the subscription skips this scan (its
  // sequence is not a multiple of every).
  std::shared_ptr<const std::string> line_for(const Subscription& subscription);

  std::size_t encodings() const { return lines_.size(); }

 private:
  const ipc::CompensatedScan& scan_;
  std::vector<std::pair<ipc::socket::BeamSpan, std::shared_ptr<const std::string>>> lines_;
};

}  // namespace tofcomp::daemon::socket
