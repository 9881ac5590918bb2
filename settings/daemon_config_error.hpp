// The one error tofcompd's configuration raises: a file that cannot be read, a YAML syntax
// error, a key that does not fit the schema, or keys that contradict one another. The message
// starts with the source ("tofcompd.yaml: ") and names the key path and the reason, or the line
// and column of a syntax error ("tofcompd.yaml:12:3: YAML syntax error: ...").
#pragma once

#include <string>

#include "core/error.hpp"

namespace tofcomp::settings {

class DaemonConfigError : public core::Error {
 public:
  explicit DaemonConfigError(const std::string& what) : core::Error(what) {}
};

}  // namespace tofcomp::settings
