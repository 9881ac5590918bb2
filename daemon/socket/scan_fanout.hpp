// One published scan made into the event lines (or compact frames) of every subscription:
// encoded once per distinct beam span and format, shared by every connection that takes it.
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

  // The event line or compact frame for a subscription; nullptr when the subscription skips this scan (its
  // sequence is not a multiple of every).
  std::shared_ptr<const std::string> line_for(const Subscription& subscription);

  std::size_t encodings() const { return lines_.size(); }

 private:
  const ipc::CompensatedScan& scan_;
  struct Encoding {
    ipc::socket::BeamSpan span;
    ipc::socket::ScanFormat format;
    std::shared_ptr<const std::string> bytes;
  };
  std::vector<Encoding> lines_;
};

}  // namespace tofcomp::daemon::socket
