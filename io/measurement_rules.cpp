#include "io/measurement_rules.hpp"

#include <cmath>
#include <unordered_set>

#include "core/lms200_limits.hpp"
#include "io/measurement_cells.hpp"
#include "io/measurement_columns.hpp"

namespace tofcomp::io {
namespace {

void check_finite(const std::optional<double>& value, MeasurementColumn column,
                  const MeasurementPlace& at) {
  if (value && !std::isfinite(*value)) {
    at.fail(column_name(column), "NaN or Inf: numbers must be finite");
  }
}

bool has_line_break(std::string_view text) {
  return text.find_first_of("\r\n") != text.npos;
}

bool has_surrounding_blanks(std::string_view text) {
  return trim_blanks(text) != text;
}

std::string number_text(double value) {
  std::string text;
  append_number_cell(text, value);
  return text;
}

// A range the device can report, and a reference distance it can see (core/lms200_limits.hpp).
void check_device_limits(const MeasurementRow& row, const MeasurementPlace& at) {
  using core::lms200::kMaxRangeMm;
  using core::lms200::kMinReferenceMm;
  const std::string limit = number_text(kMaxRangeMm);
  if (row.range_mm && (*row.range_mm < 0.0 || *row.range_mm > kMaxRangeMm)) {
    at.fail(column_name(MeasurementColumn::Range), number_text(*row.range_mm) +
                                                       " mm is outside 0.." + limit +
                                                       " mm, the ranges an LMS 200 reports");
  }
  if (row.true_range_mm &&
      (*row.true_range_mm <= kMinReferenceMm || *row.true_range_mm > kMaxRangeMm)) {
    at.fail(column_name(MeasurementColumn::TrueRange),
            number_text(*row.true_range_mm) +
                " mm is no distance an LMS 200 measures: a reference distance is more than 0 "
                "and at most " +
                limit + " mm");
  }
}

}  // namespace

void RowSequenceRules::admit(const MeasurementRow& row, const MeasurementPlace& at) {
  const std::string_view time = column_name(MeasurementColumn::Time);
  if (!std::isfinite(row.time_s)) at.fail(time, "NaN or Inf: numbers must be finite");
  if (last_time_s_ && row.time_s < *last_time_s_) {
    at.fail(time, "time goes backwards: " + number_text(row.time_s) + " after " +
                      number_text(*last_time_s_));
  }
  check_finite(row.range_mm, MeasurementColumn::Range, at);
  check_finite(row.case_temp_c, MeasurementColumn::CaseTemp, at);
  check_finite(row.ambient_c, MeasurementColumn::Ambient, at);
  check_finite(row.true_range_mm, MeasurementColumn::TrueRange, at);
  check_device_limits(row, at);
  if (row.beam && *row.beam < 0) {
    at.fail(column_name(MeasurementColumn::Beam), "a beam index must not be negative");
  }
  const bool power_on = row.power.value_or(power_on_);
  const long power_off_line = power_on == power_on_ ? power_off_line_ : at.line;
  if (row.range_mm && !power_on) {
    at.fail(column_name(MeasurementColumn::Range),
            power_off_line > 0
                ? "a range while the power is 0 (since line " + std::to_string(power_off_line) + ")"
                : std::string("a range while the power is 0"));
  }
  last_time_s_ = row.time_s;
  power_on_ = power_on;
  power_off_line_ = power_off_line;
}

void check_column_names(const std::vector<std::string>& columns, const MeasurementPlace& at) {
  std::unordered_set<std::string_view> seen;
  for (std::size_t c = 0; c < columns.size(); ++c) {
    const std::string& name = columns[c];
    if (name.empty()) at.fail("", "column " + std::to_string(c + 1) + " of the header has no name");
    // The first name is written at the start of a file without metadata, where a leading '#'
    // would read back as metadata and a byte-order mark would be skipped.
    if (has_surrounding_blanks(name) || has_line_break(name) ||
        name.find(',') != std::string::npos ||
        (c == 0 && (name.front() == '#' || name.starts_with(kUtf8ByteOrderMark)))) {
      at.fail(name,
              "a column name must hold no blanks around it, no comma, no "
              "line break, and the first must not start with '#' or a byte-order mark");
    }
    if (!seen.insert(name).second) at.fail(name, "the column is named twice in the header");
  }
  const std::string_view time = column_name(MeasurementColumn::Time);
  if (!seen.contains(time)) at.fail(time, "the header has no time_s column; it is required");
}

void check_metadata_line(const MetadataLine& line, const MeasurementPlace& at) {
  if (has_line_break(line.key) || has_line_break(line.value) ||
      line.key.find(':') != std::string::npos || has_surrounding_blanks(line.key) ||
      has_surrounding_blanks(line.value)) {
    at.fail("", "metadata '" + line.key + "' would not read back as written: it must hold no " +
                    "line break, no colon in the key and no blanks around key or value");
  }
}

void check_unknown_cell(std::string_view cell, std::string_view column,
                        const MeasurementPlace& at) {
  if (has_line_break(cell) || cell.find(',') != cell.npos) {
    at.fail(column, "a cell must not hold a comma or a line break");
  }
}

}  // namespace tofcomp::io
