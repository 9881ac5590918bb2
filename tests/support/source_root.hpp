// The checkout the tests were built from: TOFCOMP_SOURCE_ROOT, which tofcomp_add_test
// (tests/CMakeLists.txt) defines for every test executable.
#pragma once

#include <string>

namespace tofcomp::testing {

inline const std::string kSourceRoot = TOFCOMP_SOURCE_ROOT;

}  // namespace tofcomp::testing
