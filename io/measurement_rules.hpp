// The rules of the interchange CSV beyond a single cell, in one place so that the reader, the
// writer and the builder accept exactly the same tables. Every check throws
// MeasuredDataFileError at the place given.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "io/measured_data_error.hpp"
#include "io/measurement_table.hpp"

namespace tofcomp::io {

// The UTF-8 byte-order mark a file may start with (a spreadsheet's export); the reader skips it.
inline constexpr std::string_view kUtf8ByteOrderMark = "\xEF\xBB\xBF";

// What a row must satisfy given the rows before it: time_s finite and never decreasing (ties
// allowed), every number finite, range_mm within what an LMS 200 reports (0 to 81910 mm) and
// true_range_mm a distance it measures (more than 0, at most 81910 mm; core/lms200_limits.hpp),
// a beam non-negative, no range_mm while the power is off. The
// power a row sets is in force for that row's own range. One instance follows one sequence.
class RowSequenceRules {
 public:
  // Checks the row, then takes its time and power as the state the next row is checked against;
  // a row that fails leaves the state as it was.
  void admit(const MeasurementRow& row, const MeasurementPlace& at);

 private:
  std::optional<double> last_time_s_;
  bool power_on_ = true;
  long power_off_line_ = 0;
};

// The header: every name non-empty, without surrounding blanks, commas or line breaks; no name
// twice; time_s present; the first name not starting with '#' (it would read as metadata).
void check_column_names(const std::vector<std::string>& columns, const MeasurementPlace& at);

// A metadata line that reads back as itself: no line break, no colon in the key, no blanks
// around key or value.
void check_metadata_line(const MetadataLine& line, const MeasurementPlace& at);

// An unknown column's cell that reads back as itself: no comma, no line break.
void check_unknown_cell(std::string_view cell, std::string_view column, const MeasurementPlace& at);

}  // namespace tofcomp::io
