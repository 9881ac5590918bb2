#include "io/measurement_cells.hpp"

#include <charconv>
#include <cmath>
#include <system_error>

#include "io/measurement_columns.hpp"

namespace tofcomp::io {
namespace {

// A cell as a message quotes it: whole when short, else its first kQuotedCellBytes bytes and
// its length, so that a cell of a gigabyte makes a message of a line.
constexpr std::size_t kQuotedCellBytes = 40;

std::string quoted(std::string_view text) {
  std::string out = "'";
  if (text.size() <= kQuotedCellBytes) return out.append(text).append("'");
  return out.append(text.substr(0, kQuotedCellBytes))
      .append("...' (a cell of ")
      .append(std::to_string(text.size()))
      .append(" bytes)");
}

template <typename Number>
void append_shortest(std::string& out, Number value) {
  char buffer[32];  // the longest double, "-2.2250738585072014e-308", has 24 characters
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

}  // namespace

std::string_view trim_blanks(std::string_view text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  const auto last = text.find_last_not_of(" \t");
  return text.substr(first, last - first + 1);
}

double parse_number_cell(std::string_view text, std::string_view column,
                         const MeasurementPlace& at) {
  double value = 0.0;
  const char* end = text.data() + text.size();
  const auto [stop, error] = std::from_chars(text.data(), end, value);
  if (error == std::errc::result_out_of_range && stop == end) {
    at.fail(column, quoted(text) + " is beyond the range of a double");
  }
  if (error != std::errc() || stop != end) at.fail(column, quoted(text) + " is not a number");
  if (!std::isfinite(value))
    at.fail(column, quoted(text) + " is NaN or Inf: numbers must be finite");
  return value;
}

int parse_beam_cell(std::string_view text, const MeasurementPlace& at) {
  int value = 0;
  const char* end = text.data() + text.size();
  const bool digits_only = !text.empty() && text.find_first_not_of("0123456789") == text.npos;
  const auto [stop, error] = std::from_chars(text.data(), end, value);
  if (!digits_only || error != std::errc() || stop != end) {
    at.fail(column_name(MeasurementColumn::Beam),
            quoted(text) + " is not a beam index (a non-negative integer)");
  }
  return value;
}

bool parse_power_cell(std::string_view text, const MeasurementPlace& at) {
  if (text == "1") return true;
  if (text == "0") return false;
  at.fail(column_name(MeasurementColumn::Power), quoted(text) + " is not 0 or 1");
}

void append_number_cell(std::string& out, double value) {
  append_shortest(out, value);
}

void append_beam_cell(std::string& out, int beam) {
  append_shortest(out, beam);
}

void append_power_cell(std::string& out, bool on) {
  out += on ? '1' : '0';
}

}  // namespace tofcomp::io
