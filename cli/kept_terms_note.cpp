// What diagnose says about the calibration with the kept terms (cli/kept_terms_note.hpp).
#include "cli/kept_terms_note.hpp"

namespace tofcomp::cli {

std::string kept_terms_note(bool kept_any, const std::string& output) {
  if (!kept_any) {
    if (output.empty()) return {};
    return "the search kept nothing: the trained calibration (the paper's model) written to " +
           output + "\n";
  }
  if (output.empty()) {
    return "the calibration with the kept terms is not written: --calibration-output C.yaml "
           "writes it\n";
  }
  return "calibration with the kept terms written to " + output + "\n";
}

}  // namespace tofcomp::cli
