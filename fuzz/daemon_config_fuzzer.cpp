// libFuzzer target for tofcompd's configuration reader: arbitrary text through
// parse_daemon_config. Properties checked besides "no crash, no hang, no sanitizer report": the
// only exception that leaves is DaemonConfigError (anything else terminates the run), its
// message starts with the source name, and a configuration that is accepted passes validate()
// again and needs no restart against itself.
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "settings/daemon_config_yaml.hpp"

namespace {

using namespace tofcomp::settings;

void check(bool condition) {
  if (!condition) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const DaemonConfig config = parse_daemon_config(text, "fuzz.yaml", "/etc/tofcompd");
    validate(config);
    check(keys_needing_restart(config, config).empty());
    check(config.source == "fuzz.yaml");
  } catch (const DaemonConfigError& e) {
    check(std::string_view(e.what()).substr(0, 9) == "fuzz.yaml");
  }
  return 0;
}
