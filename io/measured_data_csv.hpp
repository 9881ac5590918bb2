// Reading and writing the measured-data interchange CSV (../shared/docs/data-format.md; the
// exact semantics are in io/README.md). A file written here, read and written again, is
// byte-identical, and read → write → read gives back every value bit for bit.
#pragma once

#include <array>
#include <filesystem>
#include <istream>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "io/measured_data_error.hpp"
#include "io/measurement_columns.hpp"
#include "io/measurement_rules.hpp"
#include "io/measurement_table.hpp"

namespace tofcomp::io {

// No line of measured data is longer: a longer one is an error at its line (quoting its start),
// read no further, so that a line of a gigabyte costs no more memory than this.
inline constexpr std::size_t kMaxMeasuredDataLineBytes = 1u << 16;

// Reads a whole file in one pass, in time and memory linear in its size. Throws
// MeasuredDataFileError naming `source_name`, the 1-based line and the column at the first
// fault (a line longer than kMaxMeasuredDataLineBytes included); core::Error if the stream fails.
// Unknown columns give one warning in the result.
MeasurementTable read_measured_data(std::istream& in, std::string_view source_name);

// The same from a file; core::Error if it cannot be opened.
MeasurementTable read_measured_data_file(const std::filesystem::path& file);

// Writes row by row, so a recording need not be held in memory. The metadata and the header go
// out on construction. Every row is checked as the reader would check it (and for values in
// columns the header lacks) before any of it is written, so the stream always holds a file the
// reader accepts; a MeasuredDataFileError names the line the row would have taken. Throws
// core::Error when the stream fails. After an exception the writer must not be used again.
class MeasuredDataWriter {
 public:
  MeasuredDataWriter(std::ostream& out, const std::vector<MetadataLine>& metadata,
                     std::vector<std::string> columns, std::string_view destination_name);

  void write_row(const MeasurementRow& row);

 private:
  void put_line();
  void append_known_cell(MeasurementColumn column, const MeasurementRow& row);

  std::ostream& out_;
  std::string destination_;
  std::vector<std::string> columns_;
  std::vector<std::optional<MeasurementColumn>> kinds_;  // per column; nullopt: unknown
  std::array<bool, kMeasurementColumns.size()> in_header_{};
  std::size_t unknown_columns_ = 0;
  RowSequenceRules rules_;
  long line_ = 0;  // lines written so far
  std::string buffer_;
};

// The whole table with MeasuredDataWriter; its warnings are not written.
void write_measured_data(std::ostream& out, const MeasurementTable& table,
                         std::string_view destination_name = "output");

// Atomically (io/atomic_file.hpp): a temporary file beside `file`, fsync, rename. On any error
// the previous file, if any, is left as it was.
void write_measured_data_file(const std::filesystem::path& file, const MeasurementTable& table);

}  // namespace tofcomp::io
