// The line `tofcomp diagnose` ends with when its search kept terms: where the calibration with
// them went, or, without --calibration-output, that it was not written and how to write it.
#pragma once

#include <string>

namespace tofcomp::cli {

// Empty when nothing was kept; `output` empty: no --calibration-output was given.
std::string kept_terms_note(bool kept_any, const std::string& output);

}  // namespace tofcomp::cli
