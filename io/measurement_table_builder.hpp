// A table built row by row in memory, as the twin and the daemon's recorder do. Each row is
// checked when appended, as the reader would check it, in constant time; the header is made of
// the known columns the rows use, in the format's order.
//
//   MeasurementTableBuilder builder;
//   builder.add_metadata("sensor", "LMS200");
//   builder.append({.time_s = 0.0, .case_temp_c = 22.0, .power = true});
//   builder.append({.time_s = 0.0, .range_mm = 2997.0, .beam = 90, .true_range_mm = 3000.0});
//   write_measured_data_file("run.csv", builder.finish());
#pragma once

#include <array>
#include <cstddef>
#include <string>

#include "io/measurement_columns.hpp"
#include "io/measurement_rules.hpp"
#include "io/measurement_table.hpp"

namespace tofcomp::io {

class MeasurementTableBuilder {
 public:
  // Throws MeasuredDataFileError if the line would not read back as itself (a line break, a
  // colon in the key, blanks around key or value).
  void add_metadata(std::string key, std::string value);

  // Throws MeasuredDataFileError (source "appended row N", line 0) naming the column: time going
  // backwards, NaN or Inf, a negative beam, a range while the power is 0, unknown cells. The
  // builder is unchanged then.
  void append(const MeasurementRow& row);

  std::size_t row_count() const { return table_.rows.size(); }

  // The table built so far; the builder starts afresh.
  MeasurementTable finish();

 private:
  MeasurementTable table_;
  RowSequenceRules rules_;
  std::array<bool, kMeasurementColumns.size()> used_{};
};

}  // namespace tofcomp::io
