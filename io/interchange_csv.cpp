#include "io/interchange_csv.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "io/atomic_file.hpp"

namespace tofcomp::io {
namespace {

enum class Column { Time, Range, Beam, CaseTemp, Power, Ambient, TrueRange, Unknown };

Column column_kind(const std::string& name) {
  static const std::map<std::string, Column> known = {{"time_s", Column::Time},
                                                      {"range_mm", Column::Range},
                                                      {"beam", Column::Beam},
                                                      {"case_temp_c", Column::CaseTemp},
                                                      {"power", Column::Power},
                                                      {"ambient_c", Column::Ambient},
                                                      {"true_range_mm", Column::TrueRange}};
  const auto it = known.find(name);
  return it == known.end() ? Column::Unknown : it->second;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> split_cells(std::string_view line) {
  std::vector<std::string_view> cells;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    if (comma == std::string_view::npos) {
      cells.push_back(line.substr(start));
      return cells;
    }
    cells.push_back(line.substr(start, comma - start));
    start = comma + 1;
  }
}

// Where an error is raised: the source and the line.
struct Place {
  const std::string& source;
  long line;
  [[noreturn]] void fail(const std::string& column, const std::string& reason) const {
    throw MeasurementFileError(source, line, column, reason);
  }
};

double parse_number(std::string_view text, const Place& at, const std::string& column) {
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size()) {
    at.fail(column, "'" + std::string(text) + "' is not a number");
  }
  if (!std::isfinite(value)) at.fail(column, "'" + std::string(text) + "' is NaN or Inf");
  return value;
}

long parse_beam(std::string_view text, const Place& at) {
  long value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || value < 0) {
    at.fail("beam", "'" + std::string(text) + "' is not a non-negative whole number");
  }
  return value;
}

int parse_power(std::string_view text, const Place& at) {
  if (text == "0") return 0;
  if (text == "1") return 1;
  at.fail("power", "'" + std::string(text) + "' is not 0 or 1");
}

std::string format_number(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

// What every row must satisfy given the state before it; returns the power after it.
int check_row(const MeasurementRow& row, std::optional<double> previous_time, int power,
              const Place& at) {
  if (previous_time && row.time_s < *previous_time) {
    at.fail("time_s", "time goes backwards (" + format_number(row.time_s) + " after " +
                          format_number(*previous_time) + ")");
  }
  const int now = row.power.value_or(power);
  if (row.range_mm && now == 0) at.fail("range_mm", "a range while the power is 0");
  return now;
}

void check_finite(const std::optional<double>& v, const Place& at, const std::string& column) {
  if (v && !std::isfinite(*v)) at.fail(column, "is NaN or Inf");
}

}  // namespace

MeasurementFileError::MeasurementFileError(const std::string& source, long line,
                                           const std::string& column, const std::string& reason)
    : core::Error(source + ":" + std::to_string(line) + ": " +
                  (column.empty() ? std::string() : "column " + column + ": ") + reason),
      line_(line),
      column_(column) {}

void MeasurementTable::append(const MeasurementRow& row) {
  const Place at{"in-memory table", 0};
  if (!std::isfinite(row.time_s)) at.fail("time_s", "is NaN or Inf");
  check_finite(row.range_mm, at, "range_mm");
  check_finite(row.case_temp_c, at, "case_temp_c");
  check_finite(row.ambient_c, at, "ambient_c");
  check_finite(row.true_range_mm, at, "true_range_mm");
  if (row.power && *row.power != 0 && *row.power != 1) at.fail("power", "is not 0 or 1");
  if (row.beam && *row.beam < 0) at.fail("beam", "is negative");
  int power = 1;
  for (const auto& r : rows) power = r.power.value_or(power);
  check_row(row, rows.empty() ? std::nullopt : std::optional<double>(rows.back().time_s), power,
            at);
  auto ensure = [&](bool used, const char* name) {
    if (!used) return;
    for (const auto& c : columns) {
      if (c == name) return;
    }
    columns.emplace_back(name);
  };
  ensure(true, "time_s");
  ensure(row.range_mm.has_value(), "range_mm");
  ensure(row.beam.has_value(), "beam");
  ensure(row.case_temp_c.has_value(), "case_temp_c");
  ensure(row.power.has_value(), "power");
  ensure(row.ambient_c.has_value(), "ambient_c");
  ensure(row.true_range_mm.has_value(), "true_range_mm");
  rows.push_back(row);
}

MeasurementTable read_measurements(std::istream& in, const std::string& source) {
  MeasurementTable table;
  std::string raw;
  long line_number = 0;
  bool have_header = false;
  std::vector<Column> kinds;
  std::optional<double> previous_time;
  int power = 1;
  while (std::getline(in, raw)) {
    ++line_number;
    std::string_view line(raw);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const Place at{source, line_number};
    if (!have_header) {
      if (trim(line).empty()) continue;
      if (line.front() == '#') {
        std::string_view body = trim(line.substr(1));
        const auto colon = body.find(':');
        if (colon == std::string_view::npos) {
          table.metadata.emplace_back(std::string(body), "");
        } else {
          table.metadata.emplace_back(std::string(trim(body.substr(0, colon))),
                                      std::string(trim(body.substr(colon + 1))));
        }
        continue;
      }
      std::vector<std::string> unknown;
      for (const auto cell : split_cells(line)) {
        const std::string name(trim(cell));
        if (name.empty()) at.fail("", "the header has an empty column name");
        for (const auto& seen : table.columns) {
          if (seen == name) at.fail(name, "the column is named twice in the header");
        }
        table.columns.push_back(name);
        kinds.push_back(column_kind(name));
        if (kinds.back() == Column::Unknown) unknown.push_back(name);
      }
      bool has_time = false;
      for (const auto k : kinds) has_time = has_time || k == Column::Time;
      if (!has_time) at.fail("time_s", "the header has no time_s column");
      if (!unknown.empty()) {
        std::string list;
        for (const auto& u : unknown) list += (list.empty() ? "" : ", ") + u;
        table.warnings.push_back(source + ":" + std::to_string(line_number) +
                                 ": unknown columns kept out of the analysis: " + list);
      }
      have_header = true;
      continue;
    }

    const auto cells = split_cells(line);
    if (cells.size() != kinds.size()) {
      bool blank = true;
      for (const auto c : cells) blank = blank && trim(c).empty();
      if (blank && cells.size() == 1) continue;  // an empty line
      at.fail("", "the row has " + std::to_string(cells.size()) + " cells but the header has " +
                      std::to_string(kinds.size()));
    }
    MeasurementRow row;
    row.line = line_number;
    bool any_value = false;
    bool has_time = false;
    for (std::size_t c = 0; c < cells.size(); ++c) {
      const std::string_view cell = trim(cells[c]);
      const std::string& name = table.columns[c];
      if (kinds[c] == Column::Unknown) {
        row.unknown_cells.emplace_back(cells[c]);
        any_value = any_value || !cell.empty();
        continue;
      }
      if (cell.empty()) continue;
      any_value = true;
      switch (kinds[c]) {
        case Column::Time:
          row.time_s = parse_number(cell, at, name);
          has_time = true;
          break;
        case Column::Range:
          row.range_mm = parse_number(cell, at, name);
          break;
        case Column::Beam:
          row.beam = parse_beam(cell, at);
          break;
        case Column::CaseTemp:
          row.case_temp_c = parse_number(cell, at, name);
          break;
        case Column::Power:
          row.power = parse_power(cell, at);
          break;
        case Column::Ambient:
          row.ambient_c = parse_number(cell, at, name);
          break;
        case Column::TrueRange:
          row.true_range_mm = parse_number(cell, at, name);
          break;
        case Column::Unknown:
          break;
      }
    }
    if (!any_value) continue;
    if (!has_time) at.fail("time_s", "missing time_s in a row with values");
    power = check_row(row, previous_time, power, at);
    previous_time = row.time_s;
    table.rows.push_back(std::move(row));
  }
  if (!have_header) {
    throw MeasurementFileError(source, line_number + 1, "", "no header row: the file is empty");
  }
  return table;
}

MeasurementTable read_measurements_file(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw MeasurementFileError(file, 0, "", "cannot be opened");
  return read_measurements(in, file);
}

void write_measurements(std::ostream& out, const MeasurementTable& table) {
  for (const auto& [key, value] : table.metadata) {
    out << "# " << key;
    if (!value.empty()) out << ": " << value;
    out << "\n";
  }
  std::vector<Column> kinds;
  for (std::size_t c = 0; c < table.columns.size(); ++c) {
    out << (c ? "," : "") << table.columns[c];
    kinds.push_back(column_kind(table.columns[c]));
  }
  out << "\n";
  auto cell = [](const auto& optional) {
    return optional ? format_number(static_cast<double>(*optional)) : std::string();
  };
  for (const auto& row : table.rows) {
    std::size_t unknown = 0;
    for (std::size_t c = 0; c < kinds.size(); ++c) {
      if (c) out << ',';
      switch (kinds[c]) {
        case Column::Time:
          out << format_number(row.time_s);
          break;
        case Column::Range:
          out << cell(row.range_mm);
          break;
        case Column::Beam:
          out << (row.beam ? std::to_string(*row.beam) : "");
          break;
        case Column::CaseTemp:
          out << cell(row.case_temp_c);
          break;
        case Column::Power:
          out << (row.power ? std::to_string(*row.power) : "");
          break;
        case Column::Ambient:
          out << cell(row.ambient_c);
          break;
        case Column::TrueRange:
          out << cell(row.true_range_mm);
          break;
        case Column::Unknown:
          out << (unknown < row.unknown_cells.size() ? row.unknown_cells[unknown] : "");
          ++unknown;
          break;
      }
    }
    out << "\n";
  }
}

void write_measurements_file(const std::string& file, const MeasurementTable& table) {
  write_file_atomically(file, [&](std::ostream& out) { write_measurements(out, table); });
}

}  // namespace tofcomp::io
