#include "io/measurement_table_builder.hpp"

#include <utility>

#include "io/measured_data_error.hpp"

namespace tofcomp::io {

void MeasurementTableBuilder::add_metadata(std::string key, std::string value) {
  MetadataLine line{std::move(key), std::move(value)};
  const std::string source = "metadata line " + std::to_string(table_.metadata.size() + 1);
  check_metadata_line(line, MeasurementPlace{source, 0});
  table_.metadata.push_back(std::move(line));
}

void MeasurementTableBuilder::append(const MeasurementRow& row) {
  try {
    const MeasurementPlace at{"appended row", 0};
    if (!row.unknown_cells.empty()) at.fail("", "a built table has no unknown columns");
    rules_.admit(row, at);
  } catch (const MeasuredDataFileError& error) {  // named by its number only when it fails
    throw MeasuredDataFileError("appended row " + std::to_string(table_.rows.size() + 1), 0,
                                error.column(), error.reason());
  }
  for (const MeasurementColumn column : kMeasurementColumns) {
    used_[static_cast<std::size_t>(column)] |= has_cell(row, column);
  }
  table_.rows.push_back(row);
}

MeasurementTable MeasurementTableBuilder::finish() {
  for (const MeasurementColumn column : kMeasurementColumns) {
    if (column == MeasurementColumn::Time || used_[static_cast<std::size_t>(column)]) {
      table_.columns.emplace_back(column_name(column));
    }
  }
  MeasurementTable table = std::move(table_);
  *this = MeasurementTableBuilder();
  return table;
}

}  // namespace tofcomp::io
