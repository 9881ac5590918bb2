// Scan fan-out: a short list of the spans encoded so far (subscriptions share few ranges).
#include "daemon/socket/scan_fanout.hpp"

#include "ipc/socket/compact_frame.hpp"
#include "ipc/socket/reply.hpp"

namespace tofcomp::daemon::socket {

std::shared_ptr<const std::string> ScanFanout::line_for(const Subscription& subscription) {
  if (subscription.every == 0 || scan_.sequence % subscription.every != 0) return nullptr;
  const auto span = ipc::socket::beams_clipped(subscription.beams, scan_.beams.size());
  for (const auto& encoding : lines_) {
    if (encoding.span == span && encoding.format == subscription.format) return encoding.bytes;
  }
  auto bytes = std::make_shared<const std::string>(
      subscription.format == ipc::socket::ScanFormat::Compact
          ? ipc::socket::encode_compact_frame(scan_, span)
          : ipc::socket::encode_scan_event(ipc::socket::encode_scan(scan_, span)));
  lines_.push_back({span, subscription.format, bytes});
  return bytes;
}

}  // namespace tofcomp::daemon::socket
