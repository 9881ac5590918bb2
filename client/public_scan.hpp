// The library's scan (tofcomp/client.hpp) made from what the ring and the socket decoders give:
// a CompensatedScan and the span of its beams that was carried.
#pragma once

#include <string>

#include "ipc/compensated_scan.hpp"
#include "ipc/socket/scan_json.hpp"
#include "tofcomp/client.hpp"

// Not tofcomp::client: the library exports that namespace, and this is internal.
namespace tofcomp::client_detail {

using client::Beam;
using client::Scan;

Scan public_scan(const ipc::CompensatedScan& scan, ipc::socket::BeamSpan span,
                 std::string json = {});

}  // namespace tofcomp::client_detail
