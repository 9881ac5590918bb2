// The error every reader, writer and builder of the measured-data interchange CSV raises when a
// file or a table breaks the format (../shared/docs/data-format.md, io/README.md).
#pragma once

#include <string>
#include <string_view>

#include "core/error.hpp"

namespace tofcomp::io {

// The message reads "SOURCE:LINE: column COLUMN: REASON". ":LINE" is left out when line is 0
// (a row of a table built in memory), "column COLUMN: " when the fault lies in no single column
// (an empty file, a row with more cells than the header).
class MeasuredDataFileError : public core::Error {
 public:
  MeasuredDataFileError(std::string_view source, long line, std::string_view column,
                        std::string_view reason);

  const std::string& source() const { return source_; }
  long line() const { return line_; }  // 1-based line in the file; 0 when not from a file
  const std::string& column() const { return column_; }  // empty when no single column
  const std::string& reason() const { return reason_; }

 private:
  std::string source_;
  long line_;
  std::string column_;
  std::string reason_;
};

// Where the reader, writer or builder stands: the fault it finds is raised here.
struct MeasurementPlace {
  std::string_view source;
  long line = 0;

  [[noreturn]] void fail(std::string_view column, std::string_view reason) const;
};

}  // namespace tofcomp::io
