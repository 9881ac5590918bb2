#pragma once

namespace tofcomp::cli {

// The version written into calibration files' provenance; set by CMake from project().
inline constexpr const char* kVersion = TOFCOMP_VERSION;

}  // namespace tofcomp::cli
