// Every YAML file tofcomp reads (calibration, datasheet, scenario; io/yaml_fields.hpp) is read
// strictly (issue 15): a key given twice, a NUL byte with text after it, a second document, a
// FIFO in place of the file are refused, naming the file, the line and what is wrong; yaml-cpp
// alone would keep one of the keys, or stop at the NUL, silently.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/calibration_file.hpp"
#include "io/yaml_fields.hpp"

namespace tofcomp::io {
namespace {

std::string bundled_calibration() {
  std::ifstream in(std::string(TOFCOMP_SOURCE_ROOT) + "/config/calibration.yaml");
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string refusal(const std::string& text) {
  try {
    parse_calibration_yaml(text, "c.yaml");
  } catch (const core::Error& e) {
    return e.what();
  }
  return "";
}

void replace(std::string& text, const std::string& from, const std::string& to) {
  text.replace(text.find(from), from.size(), to);
}

TEST(YamlStrict, TheBundledCalibrationReads) {
  EXPECT_EQ(refusal(bundled_calibration()), "");
}

TEST(YamlStrict, AKeyGivenTwiceIsRefusedAtItsLine) {
  std::string text = bundled_calibration();
  replace(text, "  power_w: 10\n", "  power_w: 10\n  power_w: 99\n");
  const std::string message = refusal(text);
  EXPECT_NE(message.find("c.yaml:"), std::string::npos) << message;
  EXPECT_NE(message.find(": thermal.power_w is given twice"), std::string::npos) << message;
}

TEST(YamlStrict, ANulByteIsRefusedWhateverFollowsIt) {
  std::string text = bundled_calibration();
  text.insert(text.find("thermal:"), std::string("\0", 1) + "x: 1\n");
  const std::string message = refusal(text);
  EXPECT_NE(message.find(": a NUL byte: a YAML file is text"), std::string::npos) << message;
}

TEST(YamlStrict, ASecondDocumentIsRefused) {
  const std::string message = refusal(bundled_calibration() + "---\nschema: other\n");
  EXPECT_NE(message.find("text after the end of the document"), std::string::npos) << message;
}

TEST(YamlStrict, AFifoInPlaceOfTheFileIsRefusedNotWaitedOn) {
  const std::string fifo = ::testing::TempDir() + "/calibration-fifo.yaml";
  ::unlink(fifo.c_str());
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  try {
    read_calibration_file(fifo);
    FAIL() << "read a FIFO";
  } catch (const core::Error& e) {
    EXPECT_NE(std::string(e.what()).find("a FIFO (named pipe), not a regular file"),
              std::string::npos)
        << e.what();
  }
  ::unlink(fifo.c_str());
}

}  // namespace
}  // namespace tofcomp::io
