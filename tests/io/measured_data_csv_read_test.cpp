// Reading the interchange CSV: the format document's example, line ends, metadata, column
// order, blank rows and unknown columns. Expected values are worked out by hand from the text.
#include <gtest/gtest.h>

#include <limits>

#include "io/measurement_series.hpp"
#include "measured_data_csv_test_support.hpp"

namespace tofcomp::io {
namespace {

using testing::parse;
using testing::write;

// Verbatim from ../shared/docs/data-format.md, "Example".
const std::string kFormatExample =
    "# sensor: LMS200\n"
    "# target: white board, 3 m\n"
    "time_s,range_mm,case_temp_c,power,ambient_c,true_range_mm\n"
    "0.000,,22.0000,1,22.00,\n"
    "0.000,2997,,,,3000\n"
    "0.250,3001,,,,\n"
    "0.500,2996,,,,\n"
    "1.000,,22.0625,,22.01,\n";

std::string with_crlf(const std::string& text) {
  std::string out;
  for (const char c : text) out += c == '\n' ? std::string("\r\n") : std::string(1, c);
  return out;
}

TEST(MeasuredDataCsvRead, FormatDocumentExampleRows) {
  const MeasurementTable t = parse(kFormatExample);
  ASSERT_EQ(t.metadata.size(), 2u);
  EXPECT_EQ(t.metadata[0].key, "sensor");
  EXPECT_EQ(t.metadata[0].value, "LMS200");
  EXPECT_EQ(t.metadata[1].key, "target");
  EXPECT_EQ(t.metadata[1].value, "white board, 3 m");
  EXPECT_EQ(t.columns, (std::vector<std::string>{"time_s", "range_mm", "case_temp_c", "power",
                                                 "ambient_c", "true_range_mm"}));
  EXPECT_TRUE(t.warnings.empty());
  ASSERT_EQ(t.rows.size(), 5u);

  const MeasurementRow& first = t.rows[0];  // 0.000,,22.0000,1,22.00,
  EXPECT_EQ(first.line, 4);
  EXPECT_EQ(first.time_s, 0.0);
  EXPECT_FALSE(first.range_mm);
  EXPECT_EQ(first.case_temp_c, 22.0);
  EXPECT_EQ(first.power, true);
  EXPECT_EQ(first.ambient_c, 22.0);
  EXPECT_FALSE(first.true_range_mm);
  EXPECT_FALSE(first.beam);

  const MeasurementRow& second = t.rows[1];  // 0.000,2997,,,,3000
  EXPECT_EQ(second.line, 5);
  EXPECT_EQ(second.time_s, 0.0);
  EXPECT_EQ(second.range_mm, 2997.0);
  EXPECT_EQ(second.true_range_mm, 3000.0);
  EXPECT_FALSE(second.case_temp_c);
  EXPECT_FALSE(second.power);

  EXPECT_EQ(t.rows[2].time_s, 0.25);
  EXPECT_EQ(t.rows[2].range_mm, 3001.0);
  EXPECT_FALSE(t.rows[2].true_range_mm);  // the cell is empty; the value holds in the series
  EXPECT_EQ(t.rows[3].time_s, 0.5);
  EXPECT_EQ(t.rows[3].range_mm, 2996.0);

  const MeasurementRow& last = t.rows[4];  // 1.000,,22.0625,,22.01,
  EXPECT_EQ(last.line, 8);
  EXPECT_EQ(last.time_s, 1.0);
  EXPECT_EQ(last.case_temp_c, 22.0625);
  EXPECT_EQ(last.ambient_c, 22.01);
  EXPECT_FALSE(last.range_mm);
}

TEST(MeasuredDataCsvRead, FormatDocumentExampleSeries) {
  const MeasurementTable t = parse(kFormatExample);

  const BeamRanges beam0 = beam_ranges(t, 0);
  EXPECT_EQ(beam0.time_s, (std::vector<double>{0.0, 0.25, 0.5}));
  EXPECT_EQ(beam0.range_mm, (std::vector<double>{2997.0, 3001.0, 2996.0}));
  // 3000 is set on the first range's own row and holds for the two after it.
  EXPECT_EQ(beam0.true_range_mm, (std::vector<std::optional<double>>{3000.0, 3000.0, 3000.0}));
  EXPECT_EQ(beam0.line, (std::vector<long>{5, 6, 7}));
  EXPECT_TRUE(beam_ranges(t, 1).time_s.empty());

  const TimedSamples temps = case_temperatures(t);
  EXPECT_EQ(temps.time_s, (std::vector<double>{0.0, 1.0}));
  EXPECT_EQ(temps.value, (std::vector<double>{22.0, 22.0625}));
  const TimedSamples ambient = ambient_temperatures(t);
  EXPECT_EQ(ambient.time_s, (std::vector<double>{0.0, 1.0}));
  EXPECT_EQ(ambient.value, (std::vector<double>{22.0, 22.01}));
  // power is set to 1 at 0 s, which it already was by default: no change.
  EXPECT_TRUE(power_changes(t).empty());
}

TEST(MeasuredDataCsvRead, CrlfReadsAsLf) {
  const MeasurementTable lf = parse(kFormatExample);
  const MeasurementTable crlf = parse(with_crlf(kFormatExample));
  testing::expect_same_table(lf, crlf);
  ASSERT_EQ(crlf.rows.size(), lf.rows.size());
  for (std::size_t r = 0; r < lf.rows.size(); ++r) EXPECT_EQ(crlf.rows[r].line, lf.rows[r].line);
  EXPECT_EQ(crlf.metadata[1].value, "white board, 3 m");  // no '\r' left in the value
}

TEST(MeasuredDataCsvRead, MixedLineEndsAndNoFinalLineEnd) {
  const MeasurementTable t = parse("time_s,range_mm\r\n0,1\n0.5,2\r\n1,3");
  ASSERT_EQ(t.rows.size(), 3u);
  EXPECT_EQ(t.rows[2].range_mm, 3.0);
  EXPECT_EQ(t.rows[2].line, 4);
}

TEST(MeasuredDataCsvRead, ColumnsInAnyOrder) {
  const MeasurementTable t = parse(
      "true_range_mm,ambient_c,beam,power,case_temp_c,range_mm,time_s\n"
      "1500,21.5,7,1,30.25,1499,2.5\n");
  ASSERT_EQ(t.rows.size(), 1u);
  const MeasurementRow& row = t.rows[0];
  EXPECT_EQ(row.time_s, 2.5);
  EXPECT_EQ(row.range_mm, 1499.0);
  EXPECT_EQ(row.beam, 7);
  EXPECT_EQ(row.case_temp_c, 30.25);
  EXPECT_EQ(row.power, true);
  EXPECT_EQ(row.ambient_c, 21.5);
  EXPECT_EQ(row.true_range_mm, 1500.0);
}

TEST(MeasuredDataCsvRead, MetadataKeptInOrderAndRewritten) {
  const MeasurementTable t = parse(
      "# sensor: LMS200\n"
      "#target:wall, 3 m\n"
      "# url: http://host:80/x\n"
      "# a note without a colon\n"
      "\n"
      "time_s\n"
      "0\n");
  ASSERT_EQ(t.metadata.size(), 4u);
  EXPECT_EQ(t.metadata[1].key, "target");
  EXPECT_EQ(t.metadata[1].value, "wall, 3 m");
  EXPECT_EQ(t.metadata[2].key, "url");
  EXPECT_EQ(t.metadata[2].value, "http://host:80/x");  // split at the first colon only
  EXPECT_EQ(t.metadata[3].key, "a note without a colon");
  EXPECT_EQ(t.metadata[3].value, "");
  EXPECT_EQ(write(t),
            "# sensor: LMS200\n"
            "# target: wall, 3 m\n"
            "# url: http://host:80/x\n"
            "# a note without a colon\n"
            "time_s\n"
            "0\n");
}

TEST(MeasuredDataCsvRead, RowsWithoutAnyValueAreIgnored) {
  const MeasurementTable t = parse(
      "\n"
      "time_s,range_mm,note\n"
      "0,1,\n"
      ",,\n"
      "\n"
      " , ,\t\n"
      "1,2,\n"
      "\n");
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.rows[0].line, 3);
  EXPECT_EQ(t.rows[1].line, 7);
}

TEST(MeasuredDataCsvRead, RowWithTimeAloneIsKept) {
  const MeasurementTable t = parse("time_s,range_mm\n0,\n");
  ASSERT_EQ(t.rows.size(), 1u);
  EXPECT_FALSE(t.rows[0].range_mm);
}

TEST(MeasuredDataCsvRead, BlanksAroundCellsAndNamesAreTrimmed) {
  const MeasurementTable t = parse("time_s , range_mm,\tbeam\n 0.5 ,\t3000 , 4\n");
  EXPECT_EQ(t.columns, (std::vector<std::string>{"time_s", "range_mm", "beam"}));
  ASSERT_EQ(t.rows.size(), 1u);
  EXPECT_EQ(t.rows[0].time_s, 0.5);
  EXPECT_EQ(t.rows[0].range_mm, 3000.0);
  EXPECT_EQ(t.rows[0].beam, 4);
}

TEST(MeasuredDataCsvRead, ByteOrderMarkIsSkipped) {
  const MeasurementTable t = parse("\xEF\xBB\xBFtime_s,range_mm\n0,1\n");
  EXPECT_EQ(t.columns.front(), "time_s");
  EXPECT_TRUE(t.warnings.empty());
}

// A first column name that starts with a second mark (or the first, after a blank line) would
// be written at the start of a file and read back without it: refused where it stands (found by
// the measured-data fuzzer).
TEST(MeasuredDataCsvRead, AByteOrderMarkStartingTheFirstColumnNameIsRefused) {
  for (const std::string& text : {std::string("\xEF\xBB\xBF\xEF\xBB\xBFtime_s,range_mm\n0,1\n"),
                                 std::string("\n\xEF\xBB\xBFtime_s,range_mm\n0,1\n")}) {
    try {
      parse(text);
      ADD_FAILURE() << "accepted";
    } catch (const MeasuredDataFileError& e) {
      EXPECT_NE(std::string(e.what()).find("byte-order mark"), std::string::npos) << e.what();
    }
  }
}

// An unknown column a typo away from a known one is refused only when the header lacks that one
// (measured_data_csv_error_test): beside it, it is an extra column like any other.
TEST(MeasuredDataCsvRead, AColumnNearAKnownOneTheHeaderHasIsAnExtraColumn) {
  const MeasurementTable t = parse("time_s,range_mm,beam,beams\n0,3000,1,a\n");
  ASSERT_EQ(t.warnings.size(), 1u);
  EXPECT_EQ(t.warnings[0], "data.csv:1: unknown columns kept out of the analysis: beams");
  ASSERT_EQ(t.rows.size(), 1u);
  EXPECT_EQ(t.rows[0].beam, 1);
}

TEST(MeasuredDataCsvRead, UnknownColumnsOneWarningAndKeptOnRewrite) {
  const std::string text =
      "# sensor: LMS200\n"
      "time_s,operator,range_mm,note\n"
      "0,ann,3000,first\n"
      "1,,3001,\n"
      "2,bob,3002, spaced out \n";
  const MeasurementTable t = parse(text);
  ASSERT_EQ(t.warnings.size(), 1u);
  EXPECT_EQ(t.warnings[0], "data.csv:2: unknown columns kept out of the analysis: operator, note");
  ASSERT_EQ(t.rows.size(), 3u);
  EXPECT_EQ(t.rows[0].unknown_cells, (std::vector<std::string>{"ann", "first"}));
  EXPECT_EQ(t.rows[1].unknown_cells, (std::vector<std::string>{"", ""}));
  EXPECT_EQ(t.rows[2].unknown_cells, (std::vector<std::string>{"bob", " spaced out "}));
  EXPECT_EQ(t.rows[2].range_mm, 3002.0);  // the known columns are read as usual
  EXPECT_EQ(write(t), text);              // nothing lost, byte for byte
}

TEST(MeasuredDataCsvRead, RowWithOnlyUnknownValuesIsKept) {
  const MeasurementTable t = parse("time_s,note\n0,started\n");
  ASSERT_EQ(t.rows.size(), 1u);
  EXPECT_EQ(t.rows[0].unknown_cells, std::vector<std::string>{"started"});
}

TEST(MeasuredDataCsvRead, NumberForms) {
  const MeasurementTable t = parse("time_s,range_mm\n0,-0\n0,.5\n0,5.\n0,1e3\n0,1E+3\n0,5e-324\n");
  ASSERT_EQ(t.rows.size(), 6u);
  EXPECT_EQ(testing::bits(*t.rows[0].range_mm), testing::bits(-0.0));
  EXPECT_EQ(t.rows[1].range_mm, 0.5);
  EXPECT_EQ(t.rows[2].range_mm, 5.0);
  EXPECT_EQ(t.rows[3].range_mm, 1000.0);
  EXPECT_EQ(t.rows[4].range_mm, 1000.0);
  EXPECT_EQ(t.rows[5].range_mm, std::numeric_limits<double>::denorm_min());
}

}  // namespace
}  // namespace tofcomp::io
