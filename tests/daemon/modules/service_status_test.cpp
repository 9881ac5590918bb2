// The status line the service manager and `status.state` show: a compensation path that refuses
// scans says so, and why, until a scan is published again (issue 53: it said "publishing
// compensated scans" while it refused every scan).
#include "daemon/service_status.hpp"

#include <gtest/gtest.h>

namespace tofcomp::daemon {
namespace {

TEST(ServiceStatus, ARefusedScanIsInTheStatusUntilOneIsPublished) {
  ServiceStatus status;
  status.show_scan_state();
  EXPECT_EQ(status.text(), "waiting for the first scan");
  status.scan_published();
  EXPECT_EQ(status.text(), "publishing compensated scans");
  status.scan_refused("bias-corrected range is -nan");
  EXPECT_EQ(status.text(), "refusing scans: bias-corrected range is -nan");
  status.scan_refused("bias-corrected range is -nan");
  EXPECT_EQ(status.text(), "refusing scans: bias-corrected range is -nan");
  status.scan_published();
  EXPECT_EQ(status.text(), "publishing compensated scans");
}

TEST(ServiceStatus, ScansRefusedBeforeTheFirstIsPublishedAreShownToo) {
  ServiceStatus status;
  status.show_scan_state();
  status.scan_refused("no calibration");
  EXPECT_EQ(status.text(), "refusing scans: no calibration");
  status.scan_published();
  EXPECT_EQ(status.text(), "publishing compensated scans");
}

}  // namespace
}  // namespace tofcomp::daemon
