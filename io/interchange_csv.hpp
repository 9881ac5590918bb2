// The measured-data interchange CSV (../shared/docs/data-format.md): reading with errors that
// name the line and the column, and writing so that read → write → read is lossless and a
// second write is byte-identical.
//
// Semantics implemented:
//   - `# key: value` lines before the header are metadata, kept in order;
//   - the header names the columns in any order; unknown columns give one warning naming them,
//     are kept out of the analysis, and their cells are kept for re-writing;
//   - a row with no value at all is ignored; `time_s` is required in every other row and never
//     decreases; `power` (0 or 1) holds until set again and is 1 before the first; `range_mm`
//     is rejected while the power is 0; `beam` defaults to 0; numbers must parse whole and be
//     finite.
#pragma once

#include <istream>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"

namespace tofcomp::io {

// A malformed file: the message is "SOURCE:LINE: column COLUMN: reason".
class MeasurementFileError : public core::Error {
 public:
  MeasurementFileError(const std::string& source, long line, const std::string& column,
                       const std::string& reason);
  long line() const { return line_; }
  const std::string& column() const { return column_; }

 private:
  long line_;
  std::string column_;
};

// One data row: what was sampled at time_s. Empty optionals are empty cells.
struct MeasurementRow {
  double time_s = 0.0;
  std::optional<double> range_mm;
  std::optional<long> beam;
  std::optional<double> case_temp_c;
  std::optional<int> power;
  std::optional<double> ambient_c;
  std::optional<double> true_range_mm;
  std::vector<std::string> unknown_cells;  // one per unknown column, in header order
  long line = 0;                           // in the file read, 0 for rows built in memory
};

struct MeasurementTable {
  std::vector<std::pair<std::string, std::string>> metadata;
  // Column names in file order; the known ones are time_s, range_mm, beam, case_temp_c,
  // power, ambient_c, true_range_mm. Rows built in memory need only the columns they fill.
  std::vector<std::string> columns;
  std::vector<MeasurementRow> rows;
  std::vector<std::string> warnings;

  // Appends a row, checking what the reader checks (time order, power 0/1, finite numbers, no
  // range while off); throws MeasurementFileError with line 0.
  void append(const MeasurementRow& row);
};

inline const std::vector<std::string>& known_measurement_columns() {
  static const std::vector<std::string> columns = {
      "time_s", "range_mm", "beam", "case_temp_c", "power", "ambient_c", "true_range_mm"};
  return columns;
}

MeasurementTable read_measurements(std::istream& in, const std::string& source_name);
MeasurementTable read_measurements_file(const std::string& file);

void write_measurements(std::ostream& out, const MeasurementTable& table);
// Written atomically (io/atomic_file.hpp).
void write_measurements_file(const std::string& file, const MeasurementTable& table);

}  // namespace tofcomp::io
