// MeasuredDataWriter and write_measured_data: the lines the reader reads back as they were.
#include "io/atomic_file.hpp"
#include "io/measured_data_csv.hpp"
#include "io/measurement_cells.hpp"

namespace tofcomp::io {
namespace {

std::size_t index_of(MeasurementColumn column) {
  return static_cast<std::size_t>(column);
}

void append_optional_number(std::string& out, const std::optional<double>& value) {
  if (value) append_number_cell(out, *value);
}

}  // namespace

MeasuredDataWriter::MeasuredDataWriter(std::ostream& out, const std::vector<MetadataLine>& metadata,
                                       std::vector<std::string> columns,
                                       std::string_view destination_name)
    : out_(out), destination_(destination_name), columns_(std::move(columns)) {
  const long header_line = static_cast<long>(metadata.size()) + 1;
  for (std::size_t m = 0; m < metadata.size(); ++m) {
    check_metadata_line(metadata[m], MeasurementPlace{destination_, static_cast<long>(m) + 1});
  }
  check_column_names(columns_, MeasurementPlace{destination_, header_line});

  for (const MetadataLine& line : metadata) {
    buffer_.append("# ").append(line.key);
    if (!line.value.empty()) buffer_.append(": ").append(line.value);
    put_line();
  }
  for (const std::string& name : columns_) {
    kinds_.push_back(measurement_column_named(name));
    if (kinds_.back()) {
      in_header_[index_of(*kinds_.back())] = true;
    } else {
      ++unknown_columns_;
    }
    buffer_.append(buffer_.empty() ? "" : ",").append(name);
  }
  put_line();
}

void MeasuredDataWriter::write_row(const MeasurementRow& row) {
  const MeasurementPlace at{destination_, line_ + 1};
  for (const MeasurementColumn column : kMeasurementColumns) {
    if (has_cell(row, column) && !in_header_[index_of(column)]) {
      at.fail(column_name(column), "the row has a value but the header has no such column");
    }
  }
  if (row.unknown_cells.size() != unknown_columns_) {
    at.fail("", "the row has " + std::to_string(row.unknown_cells.size()) +
                    " cells of unknown columns, the header " + std::to_string(unknown_columns_));
  }
  std::size_t unknown = 0;
  for (std::size_t c = 0; c < columns_.size(); ++c) {
    if (!kinds_[c]) check_unknown_cell(row.unknown_cells[unknown++], columns_[c], at);
  }
  rules_.admit(row, at);

  unknown = 0;
  for (std::size_t c = 0; c < columns_.size(); ++c) {
    if (c > 0) buffer_ += ',';
    if (kinds_[c]) {
      append_known_cell(*kinds_[c], row);
    } else {
      buffer_ += row.unknown_cells[unknown++];
    }
  }
  put_line();
}

void MeasuredDataWriter::put_line() {
  buffer_ += '\n';
  out_.write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
  if (!out_) throw core::Error(destination_ + ": the stream failed while writing");
  buffer_.clear();
  ++line_;
}

void MeasuredDataWriter::append_known_cell(MeasurementColumn column, const MeasurementRow& row) {
  switch (column) {
    case MeasurementColumn::Time:
      append_number_cell(buffer_, row.time_s);
      break;
    case MeasurementColumn::Range:
      append_optional_number(buffer_, row.range_mm);
      break;
    case MeasurementColumn::Beam:
      if (row.beam) append_beam_cell(buffer_, *row.beam);
      break;
    case MeasurementColumn::CaseTemp:
      append_optional_number(buffer_, row.case_temp_c);
      break;
    case MeasurementColumn::Power:
      if (row.power) append_power_cell(buffer_, *row.power);
      break;
    case MeasurementColumn::Ambient:
      append_optional_number(buffer_, row.ambient_c);
      break;
    case MeasurementColumn::TrueRange:
      append_optional_number(buffer_, row.true_range_mm);
      break;
  }
}

void write_measured_data(std::ostream& out, const MeasurementTable& table,
                         std::string_view destination_name) {
  MeasuredDataWriter writer(out, table.metadata, table.columns, destination_name);
  for (const MeasurementRow& row : table.rows) writer.write_row(row);
}

void write_measured_data_file(const std::filesystem::path& file, const MeasurementTable& table) {
  write_file_atomically(file,
                        [&](std::ostream& out) { write_measured_data(out, table, file.string()); });
}

}  // namespace tofcomp::io
