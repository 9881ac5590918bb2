// The LMS 200's Algorithm 1 inputs (config/lms200-datasheet.yaml), built into the programs: the
// datasheet the thermal fit starts from, and its prior, when none is named (tofcomp's
// --datasheet, tofcompd's recalibration.datasheet).
#pragma once

#include <filesystem>
#include <string_view>

#include "core/thermal_identification.hpp"

namespace tofcomp::io {

inline constexpr const char* kBundledDatasheetName = "the bundled LMS 200 datasheet";

// The file's text, as it was when the library was built (io/CMakeLists.txt generates it).
std::string_view bundled_lms200_datasheet_text();

// The datasheet file `file` (read_datasheet_file), or the bundled one when `file` is empty.
core::DatasheetThermalData datasheet_or_bundled(const std::filesystem::path& file);

}  // namespace tofcomp::io
