#include "io/bundled_datasheet.hpp"

#include <string>

#include "io/datasheet_file.hpp"

namespace tofcomp::io {

core::DatasheetThermalData datasheet_or_bundled(const std::filesystem::path& file) {
  return file.empty() ? parse_datasheet(std::string(bundled_lms200_datasheet_text()),
                                        kBundledDatasheetName)
                      : read_datasheet_file(file.string());
}

}  // namespace tofcomp::io
