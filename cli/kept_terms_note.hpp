// The line `tofcomp diagnose` ends with about the calibration: where the calibration with the
// kept terms went, or, without --calibration-output, that it was not written and how to write
// it; where the search kept nothing and an output was asked for, that the trained calibration
// went there (a script that asked for a calibration gets one either way).
#pragma once

#include <string>

namespace tofcomp::cli {

// Empty when nothing was kept and no output asked for; `output` empty: no --calibration-output.
std::string kept_terms_note(bool kept_any, const std::string& output);

}  // namespace tofcomp::cli
