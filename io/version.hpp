#pragma once

namespace tofcomp::io {

// The one version of tofcomp, tofcompd and the files they write (calibration provenance, the
// report): project(VERSION) in the top CMakeLists.txt, passed in by io/CMakeLists.txt.
inline constexpr const char* kVersion = TOFCOMP_VERSION;

}  // namespace tofcomp::io
