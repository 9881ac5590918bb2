// Every fault the reader must reject, each with the 1-based line of the file and the column the
// message has to name.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <streambuf>

#include "measured_data_csv_test_support.hpp"

namespace tofcomp::io {
namespace {

struct BadFile {
  std::string name;    // of the test case
  std::string text;    // the file
  long line;           // the line the error must name
  std::string column;  // the column it must name; empty: none
  std::string reason;  // a part of the reason
};

// Line 1 is metadata, line 2 the header: data rows start at line 3.
const std::string kHead =
    "# sensor: LMS200\n"
    "time_s,range_mm,beam,case_temp_c,power,ambient_c,true_range_mm\n";

std::vector<BadFile> bad_files() {
  return {
      {"time_column_missing", "# sensor: LMS200\nrange_mm,power\n3000,1\n", 2, "time_s",
       "no time_s column"},
      {"time_cell_empty", kHead + "0,3000,,,,,\n,3001,,,,,\n", 4, "time_s",
       "empty in a row that has values"},
      {"time_cell_empty_beside_unknown_value", "time_s,note\n0,a\n,b\n", 3, "time_s",
       "empty in a row that has values"},
      {"case_temp_mistyped", "# sensor: LMS200\ntime_s,range_mm,case_tmep_c\n0,3000,22\n", 2,
       "case_tmep_c", "not a known column; did you mean 'case_temp_c'?"},
      {"range_mistyped_after_rows_would_follow", "time_s,rnage_mm,power\n0,3000,1\n", 1,
       "rnage_mm", "did you mean 'range_mm'?"},
      {"time_backwards", kHead + "1,3000,,,,,\n1,3001,,,,,\n0.5,3002,,,,,\n", 5, "time_s",
       "time goes backwards: 0.5 after 1"},
      {"time_trailing_garbage", kHead + "12x,,,,,,\n", 3, "time_s", "'12x' is not a number"},
      {"range_trailing_garbage", kHead + "0,12x,,,,,\n", 3, "range_mm", "'12x' is not a number"},
      {"case_temp_two_points", kHead + "0,,,22.0.1,,,\n", 3, "case_temp_c", "not a number"},
      {"ambient_word", kHead + "0,,,,,warm,\n", 3, "ambient_c", "'warm' is not a number"},
      {"true_range_with_unit", kHead + "0,,,,,,3000mm\n", 3, "true_range_mm", "not a number"},
      {"exponent_without_digits", kHead + "0,1e,,,,,\n", 3, "range_mm", "'1e' is not a number"},
      {"plus_sign", kHead + "0,+5,,,,,\n", 3, "range_mm", "'+5' is not a number"},
      {"hexadecimal", kHead + "0,0x10,,,,,\n", 3, "range_mm", "not a number"},
      {"range_nan", kHead + "0,nan,,,,,\n", 3, "range_mm", "NaN or Inf"},
      {"time_nan", kHead + "NaN,,,,,,\n", 3, "time_s", "NaN or Inf"},
      {"case_temp_inf", kHead + "0,,,inf,,,\n", 3, "case_temp_c", "NaN or Inf"},
      {"ambient_minus_inf", kHead + "0,,,,,-inf,\n", 3, "ambient_c", "NaN or Inf"},
      {"true_range_infinity", kHead + "0,,,,,,Infinity\n", 3, "true_range_mm", "NaN or Inf"},
      {"beyond_double", kHead + "0,1e400,,,,,\n", 3, "range_mm", "beyond the range of a double"},
      {"range_after_power_off", kHead + "0,3000,,,,,\n1,,,,0,,\n2,,,22,,,\n3,3001,,,,,\n", 6,
       "range_mm", "a range while the power is 0 (since line 4)"},
      {"range_on_power_off_row", kHead + "0,3000,,,0,,\n", 3, "range_mm",
       "a range while the power is 0"},
      {"power_two", kHead + "0,,,,2,,\n", 3, "power", "'2' is not 0 or 1"},
      {"power_half", kHead + "0,,,,0.5,,\n", 3, "power", "'0.5' is not 0 or 1"},
      {"power_word", kHead + "0,,,,on,,\n", 3, "power", "'on' is not 0 or 1"},
      {"power_decimal_one", kHead + "0,,,,1.0,,\n", 3, "power", "'1.0' is not 0 or 1"},
      {"power_minus_one", kHead + "0,,,,-1,,\n", 3, "power", "'-1' is not 0 or 1"},
      {"fewer_cells", kHead + "0,3000,,,,,\n0,3000\n", 4, "beam",
       "the row has 2 cells, the header 7 columns"},
      {"more_cells", kHead + "0,3000,,,,,,\n", 3, "", "the row has 8 cells, the header 7 columns"},
      {"duplicate_known_column", "time_s,range_mm,power,range_mm\n0,1,1,1\n", 1, "range_mm",
       "named twice"},
      {"duplicate_unknown_column", "# a: b\ntime_s,note,note\n", 2, "note", "named twice"},
      {"unnamed_column", "time_s,,range_mm\n", 1, "", "column 2 of the header has no name"},
      {"empty_file", "", 1, "", "no header row"},
      {"blank_lines_only", "\n\r\n  \n", 4, "", "no header row"},
      {"metadata_only", "# sensor: LMS200\n# target: wall\n", 3, "", "no header row"},
      {"beam_negative", kHead + "0,3000,-1,,,,\n", 3, "beam", "'-1' is not a beam index"},
      {"beam_fraction", kHead + "0,3000,1.5,,,,\n", 3, "beam", "'1.5' is not a beam index"},
      {"beam_decimal_integer", kHead + "0,3000,3.0,,,,\n", 3, "beam", "'3.0' is not a beam index"},
      {"beam_word", kHead + "0,3000,left,,,,\n", 3, "beam", "'left' is not a beam index"},
      {"beam_beyond_int", kHead + "0,3000,99999999999,,,,\n", 3, "beam", "not a beam index"},
      {"carriage_return_inside_line", "time_s,note\n0,a\rb\n", 2, "", "a carriage return"},
      // The device's limits (core/lms200_limits.hpp).
      {"range_negative", kHead + "0,-5,,,,,\n", 3, "range_mm",
       "-5 mm is outside 0..81910 mm, the ranges an LMS 200 reports"},
      {"range_1e300", kHead + "0,3000,,,,,\n1,1e300,,,,,\n", 4, "range_mm",
       "1e+300 mm is outside 0..81910 mm"},
      {"range_beyond_the_device", kHead + "0,81910.5,,,,,\n", 3, "range_mm", "outside 0..81910"},
      {"true_range_negative", kHead + "0,,,,,,3000\n0,2999,,,,,-3000\n", 4, "true_range_mm",
       "-3000 mm is no distance an LMS 200 measures"},
      {"true_range_zero", kHead + "0,,,,,,0\n", 3, "true_range_mm",
       "a reference distance is more than 0 and at most 81910 mm"},
      {"true_range_1e300", kHead + "0,,,,,,1e300\n", 3, "true_range_mm", "1e+300 mm is no"},
      // Lines and cells of any length cost a bounded amount and are quoted by their start.
      {"line_too_long", kHead + "0," + std::string(70000, '9') + ",,,,,\n", 3, "",
       "a line longer than 65536 bytes (it starts '0,99999"},
  };
}

// Names the case in test listings instead of dumping its bytes.
void PrintTo(const BadFile& bad, std::ostream* out) {
  *out << bad.name;
}

class MeasuredDataCsvErrors : public ::testing::TestWithParam<BadFile> {};

TEST_P(MeasuredDataCsvErrors, NamesLineAndColumn) {
  const BadFile& bad = GetParam();
  const std::optional<MeasuredDataFileError> error = testing::read_error(bad.text);
  ASSERT_TRUE(error);
  EXPECT_EQ(error->source(), "data.csv");
  EXPECT_EQ(error->line(), bad.line);
  EXPECT_EQ(error->column(), bad.column);
  EXPECT_NE(error->reason().find(bad.reason), std::string::npos) << error->reason();
  const std::string place = "data.csv:" + std::to_string(bad.line) + ": " +
                            (bad.column.empty() ? "" : "column " + bad.column + ": ");
  EXPECT_EQ(std::string(error->what()).rfind(place, 0), 0u) << error->what();
}

std::string case_name(const ::testing::TestParamInfo<BadFile>& param) {
  return param.param.name;
}

INSTANTIATE_TEST_SUITE_P(Reader, MeasuredDataCsvErrors, ::testing::ValuesIn(bad_files()),
                         case_name);

// A stream of `bytes` bytes of '9' that counts what was read from it.
class EndlessCell : public std::streambuf {
 public:
  explicit EndlessCell(std::uint64_t bytes) : left_(bytes) {
    const std::string head = "time_s,range_mm\n0,";
    std::copy(head.begin(), head.end(), chunk_.begin());
    std::fill(chunk_.begin() + static_cast<std::ptrdiff_t>(head.size()), chunk_.end(), '9');
  }
  std::uint64_t served() const { return served_; }

 protected:
  int_type underflow() override {
    if (left_ == 0) return traits_type::eof();
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(left_, chunk_.size()));
    if (served_ > 0) std::fill(chunk_.begin(), chunk_.end(), '9');
    setg(chunk_.data(), chunk_.data(), chunk_.data() + n);
    left_ -= n;
    served_ += n;
    return traits_type::to_int_type(chunk_[0]);
  }

 private:
  std::array<char, 4096> chunk_{};
  std::uint64_t left_;
  std::uint64_t served_ = 0;
};

TEST(MeasuredDataCsvLimits, AGigabyteCellIsReadNoFurtherThanTheLineLimit) {
  EndlessCell cell(std::uint64_t{1} << 30);
  std::istream in(&cell);
  try {
    read_measured_data(in, "big.csv");
    FAIL() << "no error";
  } catch (const MeasuredDataFileError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_LT(std::string(e.what()).size(), 300u) << "the message quotes a prefix only";
  }
  // The reader stopped a chunk past the limit: memory stays bounded by the limit, not the cell.
  EXPECT_LT(cell.served(), 4 * kMaxMeasuredDataLineBytes);
}

TEST(MeasuredDataCsvLimits, ALongBadCellIsQuotedByItsStart) {
  const auto error = testing::read_error(kHead + "0," + std::string(5000, 'x') + ",,,,,\n");
  ASSERT_TRUE(error);
  EXPECT_EQ(error->column(), "range_mm");
  EXPECT_EQ(error->reason(),
            "'" + std::string(40, 'x') + "...' (a cell of 5000 bytes) is not a number");
}

TEST(MeasuredDataCsvErrorType, IsACoreErrorWithTheWholeMessage) {
  try {
    testing::parse(kHead + "0,12x,,,,,\n");
    FAIL() << "no error";
  } catch (const core::Error& error) {
    EXPECT_STREQ(error.what(), "data.csv:3: column range_mm: '12x' is not a number");
  }
}

TEST(MeasuredDataCsvErrorType, FileNameInTheMessage) {
  const std::filesystem::path file =
      std::filesystem::path(::testing::TempDir()) / "measurement_error_file.csv";
  std::ofstream(file) << "time_s,range_mm\n0,1\n-1,2\n";
  try {
    read_measured_data_file(file);
    FAIL() << "no error";
  } catch (const MeasuredDataFileError& error) {
    EXPECT_EQ(error.source(), file.string());
    EXPECT_EQ(error.line(), 3);
    EXPECT_EQ(error.column(), "time_s");
  }
  std::filesystem::remove(file);
}

TEST(MeasuredDataCsvErrorType, MissingFileIsACoreError) {
  const std::string file = ::testing::TempDir() + "/no_such_measurement_file.csv";
  try {
    read_measured_data_file(file);
    FAIL() << "no error";
  } catch (const MeasuredDataFileError&) {
    FAIL() << "a missing file is no format error";
  } catch (const core::Error& error) {
    EXPECT_NE(std::string(error.what()).find(file), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace tofcomp::io
