#include "io/measured_data_error.hpp"

namespace tofcomp::io {
namespace {

std::string message(std::string_view source, long line, std::string_view column,
                    std::string_view reason) {
  std::string text(source);
  if (line != 0) text += ":" + std::to_string(line);
  text += ": ";
  if (!column.empty()) text.append("column ").append(column).append(": ");
  text += reason;
  return text;
}

}  // namespace

MeasuredDataFileError::MeasuredDataFileError(std::string_view source, long line,
                                             std::string_view column, std::string_view reason)
    : core::Error(message(source, line, column, reason)),
      source_(source),
      line_(line),
      column_(column),
      reason_(reason) {}

void MeasurementPlace::fail(std::string_view column, std::string_view reason) const {
  throw MeasuredDataFileError(source, line, column, reason);
}

}  // namespace tofcomp::io
