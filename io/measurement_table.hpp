// One measured-data experiment as the interchange CSV holds it (../shared/docs/data-format.md):
// the metadata lines, the columns in file order and the data rows, each carrying only what was
// sampled at its instant. Read and written by io/measured_data_csv.hpp, built by
// io/measurement_table_builder.hpp, turned into per-quantity series by io/measurement_series.hpp.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace tofcomp::io {

// A `# key: value` line before the header; a line without a colon has an empty value.
struct MetadataLine {
  std::string key;
  std::string value;
};

// One data row. An empty optional is an empty cell. Members are in the order of the format's
// column table and all have initializers, so rows can be written with designated initializers
// naming only what was sampled:
//   MeasurementRow{.time_s = 0.25, .range_mm = 3001.0, .beam = 90}
struct MeasurementRow {
  double time_s = 0.0;
  std::optional<double> range_mm = std::nullopt;
  std::optional<int> beam = std::nullopt;  // of range_mm and true_range_mm; 0 when empty
  std::optional<double> case_temp_c = std::nullopt;
  // Holds until set again; on before the first row that sets it.
  std::optional<bool> power = std::nullopt;
  std::optional<double> ambient_c = std::nullopt;
  std::optional<double> true_range_mm = std::nullopt;  // holds for its beam until set again
  // The raw cells of the unknown columns, one per unknown column in header order, so that a
  // re-written file loses nothing. Empty when the table has no unknown column.
  std::vector<std::string> unknown_cells = {};
  long line = 0;  // the row's line in the file it was read from; 0 for rows built in memory
};

struct MeasurementTable {
  std::vector<MetadataLine> metadata;  // in file order
  // The header, in file order: the known names (io/measurement_columns.hpp) and unknown ones.
  std::vector<std::string> columns;
  std::vector<MeasurementRow> rows;  // sorted by time_s
  // What the reader reports without failing: one line naming the unknown columns, if any.
  std::vector<std::string> warnings;
};

}  // namespace tofcomp::io
