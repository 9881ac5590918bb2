// Where the programs find the files they ship with (the emulated scanner's scenarios, the bundled
// calibration, the diagnosis report's renderer): a directory at a fixed place relative to the
// running binary, PREFIX/share/tofcomp beside PREFIX/bin, so that no path of the build tree is
// built in and an installed tree works under any prefix. In the build tree the build copies the
// files to build/share/tofcomp, beside build/cli and build/daemon (config/CMakeLists.txt).
#pragma once

#include <filesystem>

namespace tofcomp::io {

// The directory of the running binary (/proc/self/exe) joined with TOFCOMP_DATA_FROM_BINDIR
// ("../share/tofcomp"), normalized. Throws core::Error when /proc/self/exe cannot be read.
std::filesystem::path data_directory();

}  // namespace tofcomp::io
