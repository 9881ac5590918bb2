// Scan fan-out: a short list of the spans encoded so far (subscriptions share few ranges).
#include "daemon/socket/scan_fanout.hpp"

#include "ipc/socket/reply.hpp"

namespace tofcomp::daemon::socket {

std::shared_ptr<const std::string> ScanFanout::line_for(const Subscription& subscription) {
  if (subscription.every == 0 || scan_.sequence % subscription.every != 0) return nullptr;
  const auto span = ipc::socket::beams_clipped(subscription.beams, scan_.beams.size());
  for (const auto& [encoded_span, line] : lines_) {
    if (encoded_span == span) return line;
  }
  auto line = std::make_shared<const std::string>(
      ipc::socket::encode_scan_event(ipc::socket::encode_scan(scan_, span)));
  lines_.emplace_back(span, line);
  return line;
}

}  // namespace tofcomp::daemon::socket
