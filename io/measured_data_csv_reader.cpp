// read_measured_data: one pass over the lines, metadata until the header, then data rows.
#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>

#include "io/closest_names.hpp"
#include "io/measured_data_csv.hpp"
#include "io/measurement_cells.hpp"
#include "io/measurement_columns.hpp"
#include "io/measurement_rules.hpp"

namespace tofcomp::io {
namespace {

// Splits at every comma into `cells`, reusing its storage.
void split_cells(std::string_view line, std::vector<std::string_view>& cells) {
  cells.clear();
  for (;;) {
    const std::size_t comma = line.find(',');
    cells.push_back(line.substr(0, comma));
    if (comma == std::string_view::npos) return;
    line.remove_prefix(comma + 1);
  }
}

// The lines of a stream, each at most max_bytes long: a longer one is an error at its line,
// quoting its start, and nothing more of it is read.
class BoundedLines {
 public:
  BoundedLines(std::istream& in, std::string_view source, std::size_t max_bytes)
      : in_(in), source_(source), max_bytes_(max_bytes) {}

  // The next line without its '\n' (valid until the next call); false at the end.
  bool next(std::string_view& line, long number) {
    for (;;) {
      const std::size_t newline = buffer_.find('\n', scanned_);
      if (newline != std::string::npos) {
        check_length(newline - start_, number);
        line = std::string_view(buffer_).substr(start_, newline - start_);
        start_ = scanned_ = newline + 1;
        return true;
      }
      check_length(buffer_.size() - start_, number);
      if (ended_) {
        if (start_ == buffer_.size()) return false;
        line = std::string_view(buffer_).substr(start_);
        start_ = scanned_ = buffer_.size();
        return true;
      }
      buffer_.erase(0, start_);
      scanned_ = buffer_.size();
      start_ = 0;
      const std::size_t had = buffer_.size();
      buffer_.resize(had + kChunkBytes);
      in_.read(buffer_.data() + had, static_cast<std::streamsize>(kChunkBytes));
      buffer_.resize(had + static_cast<std::size_t>(in_.gcount()));
      if (in_.bad()) {
        throw core::Error(std::string(source_) + ": the stream failed while reading");
      }
      ended_ = !in_;
    }
  }

 private:
  static constexpr std::size_t kChunkBytes = 1u << 16;
  static constexpr std::size_t kQuotedStartBytes = 40;

  void check_length(std::size_t length, long number) const {
    if (length <= max_bytes_) return;
    MeasurementPlace{source_, number}.fail(
        "", "a line longer than " + std::to_string(max_bytes_) + " bytes (it starts '" +
                std::string(std::string_view(buffer_).substr(start_, kQuotedStartBytes)) +
                "...'); no line of measured data is that long, and it is not read");
  }

  std::istream& in_;
  std::string_view source_;
  std::size_t max_bytes_;
  std::string buffer_;
  std::size_t start_ = 0;    // where the next line starts in buffer_
  std::size_t scanned_ = 0;  // buffer_ holds no '\n' from start_ up to here
  bool ended_ = false;
};

class MeasurementCsvReader {
 public:
  explicit MeasurementCsvReader(std::string_view source) : source_(source) {}

  // One line of the file, without its line end.
  void take_line(std::string_view line, long number) {
    const MeasurementPlace at{source_, number};
    if (number == 1 && line.starts_with(kUtf8ByteOrderMark)) {
      line.remove_prefix(kUtf8ByteOrderMark.size());
    }
    if (line.find('\r') != std::string_view::npos) {
      at.fail("", "a carriage return inside a line (line ends are \\n or \\r\\n)");
    }
    if (trim_blanks(line).empty()) return;  // a row with no value at all
    if (!kinds_.empty()) {
      take_row(line, at);
    } else if (line.front() == '#') {
      take_metadata(line.substr(1));
    } else {
      take_header(line, at);
    }
  }

  MeasurementTable finish(long lines) && {
    if (kinds_.empty()) {
      MeasurementPlace{source_, lines + 1}.fail("", "no header row (the file is empty)");
    }
    return std::move(table_);
  }

 private:
  void take_metadata(std::string_view body) {
    const std::size_t colon = body.find(':');
    if (colon == std::string_view::npos) {
      table_.metadata.push_back({std::string(trim_blanks(body)), ""});
    } else {
      table_.metadata.push_back({std::string(trim_blanks(body.substr(0, colon))),
                                 std::string(trim_blanks(body.substr(colon + 1)))});
    }
  }

  void take_header(std::string_view line, const MeasurementPlace& at) {
    split_cells(line, cells_);
    std::string unknown;
    for (const std::string_view cell : cells_) {
      const std::string_view name = trim_blanks(cell);
      table_.columns.emplace_back(name);
      kinds_.push_back(measurement_column_named(name));
      if (!kinds_.back()) unknown.append(unknown.empty() ? "" : ", ").append(name);
    }
    check_column_names(table_.columns, at);
    refuse_mistyped_columns(at);
    if (!unknown.empty()) {
      table_.warnings.push_back(std::string(source_) + ":" + std::to_string(at.line) +
                                ": unknown columns kept out of the analysis: " + unknown);
    }
  }

  // An unknown column a typo away from a known one the header lacks is that column mistyped
  // ("case_tmep_c"): read on, the data would fail later for want of it, or be read without it.
  // Refused at the header, naming the known name. An unknown column far from every known name,
  // or near one the header also has, is an extra column, kept out with a warning.
  void refuse_mistyped_columns(const MeasurementPlace& at) const {
    std::vector<std::string> absent;
    for (const MeasurementColumn column : kMeasurementColumns) {
      if (std::find(kinds_.begin(), kinds_.end(), column) == kinds_.end()) {
        absent.emplace_back(column_name(column));
      }
    }
    for (std::size_t i = 0; i < kinds_.size(); ++i) {
      if (kinds_[i]) continue;
      const std::vector<std::string> near = closest_names(table_.columns[i], absent);
      if (!near.empty()) {
        at.fail(table_.columns[i], "not a known column; did you mean '" + near.front() + "'?");
      }
    }
  }

  void take_row(std::string_view line, const MeasurementPlace& at) {
    split_cells(line, cells_);
    if (cells_.size() != kinds_.size()) {
      const std::string counts = "the row has " + std::to_string(cells_.size()) +
                                 " cells, the header " + std::to_string(kinds_.size()) + " columns";
      at.fail(cells_.size() < kinds_.size() ? std::string_view(table_.columns[cells_.size()])
                                            : std::string_view(),
              counts);
    }
    MeasurementRow row;
    row.line = at.line;
    bool has_value = false;
    bool has_time = false;
    for (std::size_t c = 0; c < cells_.size(); ++c) {
      const std::string_view cell = trim_blanks(cells_[c]);
      has_value = has_value || !cell.empty();
      if (!kinds_[c]) {
        row.unknown_cells.emplace_back(cells_[c]);
      } else if (!cell.empty()) {
        has_time = has_time || *kinds_[c] == MeasurementColumn::Time;
        take_cell(*kinds_[c], cell, row, at);
      }
    }
    if (!has_value) return;
    if (!has_time) at.fail(column_name(MeasurementColumn::Time), "empty in a row that has values");
    rules_.admit(row, at);
    table_.rows.push_back(std::move(row));
  }

  static void take_cell(MeasurementColumn column, std::string_view cell, MeasurementRow& row,
                        const MeasurementPlace& at) {
    const std::string_view name = column_name(column);
    switch (column) {
      case MeasurementColumn::Time:
        row.time_s = parse_number_cell(cell, name, at);
        break;
      case MeasurementColumn::Range:
        row.range_mm = parse_number_cell(cell, name, at);
        break;
      case MeasurementColumn::Beam:
        row.beam = parse_beam_cell(cell, at);
        break;
      case MeasurementColumn::CaseTemp:
        row.case_temp_c = parse_number_cell(cell, name, at);
        break;
      case MeasurementColumn::Power:
        row.power = parse_power_cell(cell, at);
        break;
      case MeasurementColumn::Ambient:
        row.ambient_c = parse_number_cell(cell, name, at);
        break;
      case MeasurementColumn::TrueRange:
        row.true_range_mm = parse_number_cell(cell, name, at);
        break;
    }
  }

  std::string_view source_;
  MeasurementTable table_;
  std::vector<std::optional<MeasurementColumn>> kinds_;  // empty until the header is read
  std::vector<std::string_view> cells_;
  RowSequenceRules rules_;
};

}  // namespace

MeasurementTable read_measured_data(std::istream& in, std::string_view source_name) {
  MeasurementCsvReader reader(source_name);
  BoundedLines lines(in, source_name, kMaxMeasuredDataLineBytes);
  std::string_view text;
  long number = 0;
  while (lines.next(text, number + 1)) {
    ++number;
    if (text.ends_with('\r')) text.remove_suffix(1);
    reader.take_line(text, number);
  }
  return std::move(reader).finish(number);
}

MeasurementTable read_measured_data_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw core::Error(file.string() + ": cannot be opened: " + std::strerror(errno));
  return read_measured_data(in, file.string());
}

}  // namespace tofcomp::io
