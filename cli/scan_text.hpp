// A compensated scan as `tofcomp query` and `tofcomp shm-dump` print it for people: a header line
// (sequence, time in UTC to the millisecond, junction and case temperatures, calibration, the
// beams shown) and a table of the beams, a value that does not exist as "-". The one text form of
// a scan; its JSON form is the socket protocol's (ipc/socket/scan_json.hpp).
#pragma once

#include <string>

#include "ipc/compensated_scan.hpp"
#include "ipc/socket/scan_json.hpp"

namespace tofcomp::cli {

// The beams of span (within scan.beams) as text lines, each ending in a newline.
std::string scan_text(const ipc::CompensatedScan& scan, ipc::socket::BeamSpan span);

}  // namespace tofcomp::cli
