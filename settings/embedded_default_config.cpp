// The default configuration built into tofcompd; its text is generated from
// config/tofcompd.yaml by settings/CMakeLists.txt (embedded_default_config_text.cpp).
#include "settings/embedded_default_config.hpp"

#include "io/data_directory.hpp"
#include "settings/daemon_config_yaml.hpp"

namespace tofcomp::settings {

std::filesystem::path embedded_default_config_directory() {
  return io::data_directory();
}

DaemonConfig embedded_default_config(const std::filesystem::path& base_directory) {
  return parse_daemon_config(embedded_default_config_text(),
                             "built-in default (config/tofcompd.yaml)", base_directory);
}

}  // namespace tofcomp::settings
