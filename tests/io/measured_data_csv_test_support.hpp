// Shared by the interchange CSV tests: reading and writing through strings, catching the error a
// text raises, and comparing tables value for value, bit for bit.
#pragma once

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <optional>
#include <sstream>
#include <string>

#include "io/measured_data_csv.hpp"

namespace tofcomp::io::testing {

inline MeasurementTable parse(const std::string& text) {
  std::istringstream in(text);
  return read_measured_data(in, "data.csv");
}

inline std::string write(const MeasurementTable& table) {
  std::ostringstream out;
  write_measured_data(out, table, "out.csv");
  return out.str();
}

// The error reading `text` raises; fails the test if it raises none.
inline std::optional<MeasuredDataFileError> read_error(const std::string& text) {
  try {
    parse(text);
  } catch (const MeasuredDataFileError& error) {
    return error;
  }
  ADD_FAILURE() << "no error for:\n" << text;
  return std::nullopt;
}

inline std::uint64_t bits(double value) {
  return std::bit_cast<std::uint64_t>(value);
}

inline void expect_same_number(const std::optional<double>& a, const std::optional<double>& b,
                               const char* what, std::size_t row) {
  ASSERT_EQ(a.has_value(), b.has_value()) << what << " of row " << row;
  if (a) {
    EXPECT_EQ(bits(*a), bits(*b)) << what << " of row " << row << ": " << *a << " vs " << *b;
  }
}

// Same metadata, columns and rows (every double bit for bit); lines and warnings not compared.
inline void expect_same_table(const MeasurementTable& a, const MeasurementTable& b) {
  ASSERT_EQ(a.metadata.size(), b.metadata.size());
  for (std::size_t m = 0; m < a.metadata.size(); ++m) {
    EXPECT_EQ(a.metadata[m].key, b.metadata[m].key);
    EXPECT_EQ(a.metadata[m].value, b.metadata[m].value);
  }
  EXPECT_EQ(a.columns, b.columns);
  ASSERT_EQ(a.rows.size(), b.rows.size());
  for (std::size_t r = 0; r < a.rows.size(); ++r) {
    const MeasurementRow& x = a.rows[r];
    const MeasurementRow& y = b.rows[r];
    expect_same_number(x.time_s, y.time_s, "time_s", r);
    expect_same_number(x.range_mm, y.range_mm, "range_mm", r);
    EXPECT_EQ(x.beam, y.beam) << "beam of row " << r;
    expect_same_number(x.case_temp_c, y.case_temp_c, "case_temp_c", r);
    EXPECT_EQ(x.power, y.power) << "power of row " << r;
    expect_same_number(x.ambient_c, y.ambient_c, "ambient_c", r);
    expect_same_number(x.true_range_mm, y.true_range_mm, "true_range_mm", r);
    EXPECT_EQ(x.unknown_cells, y.unknown_cells) << "unknown cells of row " << r;
  }
}

}  // namespace tofcomp::io::testing
