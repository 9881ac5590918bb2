// A scan from the LMS 200 driver as the pipeline takes it: every distance code in millimetres,
// the reserved codes (no echo, dazzle, ...: hal/lms2xx/measuring_mode.hpp) marked as no echo,
// the angles of the variant (180°: beam 0 at 0°; 100°: beam 0 at 40°, the listing's
// convention), the time on the daemon's clock and the wall-clock arrival time.
#pragma once

#include "hal/lms2xx/commands.hpp"
#include "hal/lms2xx/host_driver.hpp"
#include "realtime/raw_scan.hpp"

namespace tofcomp::daemon {

realtime::RawScan to_raw_scan(const hal::lms2xx::HostScan& scan,
                              const hal::lms2xx::Variant& variant, double time_s);

}  // namespace tofcomp::daemon
