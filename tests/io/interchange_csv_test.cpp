#include "io/interchange_csv.hpp"

#include <gtest/gtest.h>

#include <random>
#include <sstream>

namespace tofcomp::io {
namespace {

MeasurementTable parse(const std::string& text) {
  std::istringstream in(text);
  return read_measurements(in, "data.csv");
}

std::string write(const MeasurementTable& table) {
  std::ostringstream out;
  write_measurements(out, table);
  return out.str();
}

// The example of ../shared/docs/data-format.md, checked by hand.
TEST(InterchangeCsv, FormatDocumentExample) {
  const MeasurementTable t = parse(
      "# sensor: LMS200\n# target: white board, 3 m\n"
      "time_s,range_mm,case_temp_c,power,ambient_c,true_range_mm\n"
      "0.000,,22.0000,1,22.00,\n0.000,2997,,,,3000\n0.250,3001,,,,\n0.500,2996,,,,\n"
      "1.000,,22.0625,,22.01,\n");
  ASSERT_EQ(t.metadata.size(), 2u);
  EXPECT_EQ(t.metadata[1].first, "target");
  EXPECT_EQ(t.metadata[1].second, "white board, 3 m");
  ASSERT_EQ(t.rows.size(), 5u);
  EXPECT_EQ(*t.rows[0].power, 1);
  EXPECT_DOUBLE_EQ(*t.rows[0].case_temp_c, 22.0);
  EXPECT_DOUBLE_EQ(*t.rows[1].range_mm, 2997.0);
  EXPECT_DOUBLE_EQ(*t.rows[1].true_range_mm, 3000.0);
  EXPECT_FALSE(t.rows[2].true_range_mm.has_value());
  EXPECT_DOUBLE_EQ(t.rows[3].time_s, 0.5);
  EXPECT_DOUBLE_EQ(*t.rows[4].ambient_c, 22.01);
  EXPECT_EQ(t.rows[4].line, 8);  // two metadata lines, the header, four rows before it
  EXPECT_TRUE(t.warnings.empty());
}

TEST(InterchangeCsv, CrlfBlankRowsAndColumnOrder) {
  const MeasurementTable t = parse("range_mm,time_s\r\n3000,0\r\n,\r\n3001,0.5\r\n");
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_DOUBLE_EQ(*t.rows[1].range_mm, 3001.0);
  EXPECT_DOUBLE_EQ(t.rows[1].time_s, 0.5);
}

TEST(InterchangeCsv, UnknownColumnsWarnOnceAndSurviveRewrite) {
  const std::string text = "time_s,operator,range_mm,note\n0,ann,3000,x\n1,,3001,\n2,bob,3002,y\n";
  const MeasurementTable t = parse(text);
  ASSERT_EQ(t.warnings.size(), 1u);
  EXPECT_NE(t.warnings[0].find("operator, note"), std::string::npos) << t.warnings[0];
  EXPECT_EQ(write(t), text);
}

struct BadFile {
  const char* text;
  long line;
  const char* column;
  const char* reason;
};

class InterchangeCsvErrors : public ::testing::TestWithParam<BadFile> {};

TEST_P(InterchangeCsvErrors, NameTheLineAndColumn) {
  const BadFile& bad = GetParam();
  try {
    parse(bad.text);
    FAIL() << "no error for: " << bad.text;
  } catch (const MeasurementFileError& e) {
    EXPECT_EQ(e.line(), bad.line) << e.what();
    EXPECT_EQ(e.column(), bad.column) << e.what();
    EXPECT_NE(std::string(e.what()).find(bad.reason), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind("data.csv:", 0), 0u) << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(
    EveryRejection, InterchangeCsvErrors,
    ::testing::Values(BadFile{"range_mm\n3000\n", 1, "time_s", "no time_s column"},
                      BadFile{"time_s,range_mm\n0,3000\n,3001\n", 3, "time_s", "missing time_s"},
                      BadFile{"time_s,range_mm\n1,3000\n0.5,3001\n", 3, "time_s", "backwards"},
                      BadFile{"time_s,range_mm\n0,30x0\n", 2, "range_mm", "'30x0' is not a number"},
                      BadFile{"time_s,case_temp_c\n0,NaN\n", 2, "case_temp_c", "NaN or Inf"},
                      BadFile{"time_s,case_temp_c\n0,inf\n", 2, "case_temp_c", "NaN or Inf"},
                      BadFile{"time_s,range_mm,power\n0,,0\n1,3000,\n", 3, "range_mm",
                              "power is 0"},
                      BadFile{"time_s,range_mm,power\n0,3000,0\n", 2, "range_mm", "power is 0"},
                      BadFile{"time_s,power\n0,2\n", 2, "power", "not 0 or 1"},
                      BadFile{"time_s,power\n0,1.0\n", 2, "power", "not 0 or 1"},
                      BadFile{"time_s,range_mm\n0,3000,7\n", 2, "", "3 cells but the header has 2"},
                      BadFile{"time_s,range_mm,time_s\n", 1, "time_s", "named twice"},
                      BadFile{"time_s,beam,range_mm\n0,-1,3000\n", 2, "beam", "non-negative whole"},
                      BadFile{"# only: metadata\n", 2, "", "no header row"}));

// Random tables with awkward doubles survive write → read exactly, and a second write is
// byte-identical.
TEST(InterchangeCsv, RoundTripIsExact) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> any(-1e6, 1e6);
  const double awkward[] = {0.1, 1e-300, 22.0625, -0.0, 3000.0, 1.0 / 3.0, 5e-324, 1e300};
  MeasurementTable t;
  t.metadata = {{"sensor", "LMS200"}, {"note", "round trip"}};
  t.columns = {"time_s", "beam", "range_mm", "case_temp_c", "power", "ambient_c", "true_range_mm"};
  double time = 0.0;
  for (int k = 0; k < 2000; ++k) {
    MeasurementRow row;
    time += std::abs(any(rng)) * 1e-6;
    row.time_s = time;
    switch (k % 4) {
      case 0:
        row.range_mm = k % 8 == 0 ? awkward[k / 8 % 8] : any(rng);
        row.beam = k % 3;
        break;
      case 1:
        row.case_temp_c = any(rng);
        row.ambient_c = awkward[k % 8];
        break;
      case 2:
        row.true_range_mm = any(rng);
        break;
      default:
        row.power = 1;
    }
    t.append(row);
  }
  const std::string first = write(t);
  const MeasurementTable back = parse(first);
  ASSERT_EQ(back.rows.size(), t.rows.size());
  for (std::size_t i = 0; i < t.rows.size(); ++i) {
    EXPECT_EQ(back.rows[i].time_s, t.rows[i].time_s);
    EXPECT_EQ(back.rows[i].range_mm, t.rows[i].range_mm) << i;
    EXPECT_EQ(back.rows[i].case_temp_c, t.rows[i].case_temp_c);
    EXPECT_EQ(back.rows[i].ambient_c, t.rows[i].ambient_c);
    EXPECT_EQ(back.rows[i].true_range_mm, t.rows[i].true_range_mm);
    EXPECT_EQ(back.rows[i].beam, t.rows[i].beam);
    EXPECT_EQ(back.rows[i].power, t.rows[i].power);
  }
  EXPECT_EQ(std::signbit(*back.rows[24].range_mm), true);  // -0.0 kept
  EXPECT_EQ(write(back), first);
  EXPECT_EQ(back.metadata, t.metadata);
}

TEST(InterchangeCsv, AppendChecksWhatTheReaderChecks) {
  MeasurementTable t;
  MeasurementRow row;
  row.time_s = 1.0;
  row.power = 0;
  t.append(row);
  MeasurementRow range;
  range.time_s = 2.0;
  range.range_mm = 3000.0;
  EXPECT_THROW(t.append(range), MeasurementFileError);
  range.time_s = 0.5;
  range.range_mm.reset();
  EXPECT_THROW(t.append(range), MeasurementFileError);
}

}  // namespace
}  // namespace tofcomp::io
