// libFuzzer target for the twin scenario reader (sim/scenario_yaml.hpp): arbitrary text as a
// scenario. Properties checked besides "no crash, no hang, no sanitizer report": the only
// exception that leaves is core::Error (anything else ends the run), its message starting with
// the source; an accepted scenario passes its own validation again. A `base:` in the text is
// looked up beside the source, in a directory that does not exist: it fails as a missing file.
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "core/error.hpp"
#include "sim/scenario_yaml.hpp"

namespace {

using namespace tofcomp;

constexpr const char* kSource = "/nonexistent/tofcomp-fuzz/scenario.yaml";

void check(bool condition) {
  if (!condition) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const sim::Scenario scenario = sim::parse_scenario_yaml(text, kSource);
    scenario.validate();
  } catch (const core::Error& e) {
    check(std::string_view(e.what()).starts_with(kSource));
  } catch (...) {
    std::abort();
  }
  return 0;
}
