// The LMS 200's Algorithm 1 inputs (config/lms200-datasheet.yaml), built into tofcomp: the
// datasheet the thermal fit starts from, and its prior, when no --datasheet is given.
#pragma once

#include <string_view>

namespace tofcomp::cli {

inline constexpr const char* kBundledDatasheetName = "the bundled LMS 200 datasheet";

// The file's text, as it was when tofcomp was built (cli/CMakeLists.txt generates it).
std::string_view bundled_lms200_datasheet_text();

}  // namespace tofcomp::cli
