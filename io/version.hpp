#pragma once

namespace tofcomp::io {

// The version written into calibration files' provenance; set by CMake from project().
inline constexpr const char* kVersion = TOFCOMP_VERSION;

}  // namespace tofcomp::io
