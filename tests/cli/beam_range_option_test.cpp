// --beams of `tofcomp query` and `tofcomp shm-dump` (cli/beam_range_option.hpp).
#include "cli/beam_range_option.hpp"

#include <gtest/gtest.h>

#include "core/error.hpp"

namespace tofcomp::cli {
namespace {

using ipc::socket::BeamRange;

TEST(BeamRangeOption, RangeOneIndexOrEveryBeam) {
  EXPECT_EQ(parse_beam_range("178:182"), (BeamRange{178, 182}));
  EXPECT_EQ(parse_beam_range("180"), (BeamRange{180, 180}));
  EXPECT_EQ(parse_beam_range("0:65535"), (BeamRange{0, 65535}));
  EXPECT_EQ(parse_beam_range(""), std::nullopt);
}

TEST(BeamRangeOption, MalformedOrReversedIsAnErrorNamingTheText) {
  for (const char* bad : {"5:3", "a", "1:", ":4", "-1:2", "65536", "1:2:3"}) {
    try {
      parse_beam_range(bad);
      ADD_FAILURE() << bad;
    } catch (const core::InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("'") + bad + "'"), std::string::npos);
    }
  }
}

}  // namespace
}  // namespace tofcomp::cli
