// What `tofcomp diagnose` says about the calibration with the terms its search kept
// (cli/kept_terms_note.hpp): without --calibration-output it says it was not written, and how;
// with it and nothing kept, that the trained calibration was written.
#include "cli/kept_terms_note.hpp"

#include <gtest/gtest.h>

namespace tofcomp::cli {
namespace {

TEST(KeptTermsNote, KeptWithoutAnOutputSaysItIsNotWrittenAndHowToWriteIt) {
  EXPECT_EQ(kept_terms_note(true, ""),
            "the calibration with the kept terms is not written: --calibration-output C.yaml "
            "writes it\n");
}

TEST(KeptTermsNote, KeptWithAnOutputNamesTheFile) {
  EXPECT_EQ(kept_terms_note(true, "out/c.yaml"),
            "calibration with the kept terms written to out/c.yaml\n");
}

TEST(KeptTermsNote, NothingKeptWithoutAnOutputSaysNothing) {
  EXPECT_EQ(kept_terms_note(false, ""), "");
}

TEST(KeptTermsNote, NothingKeptWithAnOutputSaysTheTrainedCalibrationWentThere) {
  EXPECT_EQ(kept_terms_note(false, "out/c.yaml"),
            "the search kept nothing: the trained calibration (the paper's model) written to "
            "out/c.yaml\n");
}

}  // namespace
}  // namespace tofcomp::cli
