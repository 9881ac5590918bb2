// libFuzzer target for the calibration file reader (io/calibration_file.hpp): arbitrary text as
// a calibration file. Properties checked besides "no crash, no hang, no sanitizer report": the
// only exception that leaves is core::Error (a YamlSchemaError or a core::InvalidInput; anything
// else ends the run), its message starting with the source; an accepted calibration written and
// read again is the same calibration, its second writing byte for byte the first.
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "core/error.hpp"
#include "io/calibration_file.hpp"

namespace {

using namespace tofcomp;

void check(bool condition) {
  if (!condition) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  core::Calibration calibration;
  try {
    calibration = io::parse_calibration_yaml(text, "fuzz.yaml");
  } catch (const core::Error& e) {
    check(std::string_view(e.what()).starts_with("fuzz.yaml"));
    return 0;
  } catch (...) {
    std::abort();
  }
  const std::string first = io::calibration_to_yaml(calibration);
  const core::Calibration again = io::parse_calibration_yaml(first, "rewritten.yaml");
  check(io::calibration_to_yaml(again) == first);
  return 0;
}
