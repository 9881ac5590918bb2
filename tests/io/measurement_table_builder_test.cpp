// Building a table row by row: the header from the columns used, the reader's checks at every
// append, and a failed append that leaves the builder as it was.
#include "io/measurement_table_builder.hpp"

#include <gtest/gtest.h>

#include <limits>

#include "measured_data_csv_test_support.hpp"

namespace tofcomp::io {
namespace {

MeasuredDataFileError append_error(MeasurementTableBuilder& builder, const MeasurementRow& row) {
  try {
    builder.append(row);
  } catch (const MeasuredDataFileError& error) {
    return error;
  }
  ADD_FAILURE() << "no error";
  return MeasuredDataFileError("", 0, "", "");
}

TEST(MeasurementTableBuilder, HeaderHoldsTheColumnsUsedInTheFormatOrder) {
  MeasurementTableBuilder builder;
  builder.add_metadata("source", "tofcomp digital twin");
  builder.append({.time_s = 0.0, .true_range_mm = 3000.0});
  builder.append({.time_s = 0.0, .case_temp_c = 22.0, .power = true});
  builder.append({.time_s = 0.0125, .range_mm = 2997.0, .beam = 90});
  const MeasurementTable table = builder.finish();
  EXPECT_EQ(table.columns, (std::vector<std::string>{"time_s", "range_mm", "beam", "case_temp_c",
                                                     "power", "true_range_mm"}));
  EXPECT_EQ(testing::write(table),
            "# source: tofcomp digital twin\n"
            "time_s,range_mm,beam,case_temp_c,power,true_range_mm\n"
            "0,,,,,3000\n"
            "0,,,22,1,\n"
            "0.0125,2997,90,,,\n");
  EXPECT_EQ(builder.row_count(), 0u);  // finish starts afresh
  EXPECT_EQ(builder.finish().columns, std::vector<std::string>{"time_s"});
}

TEST(MeasurementTableBuilder, AppendChecksAsTheReaderDoes) {
  MeasurementTableBuilder builder;
  builder.append({.time_s = 1.0, .range_mm = 3000.0});

  const MeasuredDataFileError backwards = append_error(builder, {.time_s = 0.5});
  EXPECT_EQ(backwards.source(), "appended row 2");
  EXPECT_EQ(backwards.line(), 0);
  EXPECT_EQ(backwards.column(), "time_s");
  EXPECT_STREQ(backwards.what(), "appended row 2: column time_s: time goes backwards: 0.5 after 1");

  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(append_error(builder, {.time_s = 2.0, .case_temp_c = nan}).column(), "case_temp_c");
  EXPECT_EQ(
      append_error(builder, {.time_s = 2.0, .ambient_c = -std::numeric_limits<double>::infinity()})
          .column(),
      "ambient_c");
  EXPECT_EQ(append_error(builder, {.time_s = 2.0, .beam = -3}).column(), "beam");
  EXPECT_EQ(append_error(builder, {.time_s = 2.0, .range_mm = 1.0, .power = false}).column(),
            "range_mm");
  EXPECT_EQ(append_error(builder, {.time_s = 2.0, .unknown_cells = {"x"}}).column(), "");

  // None of the failed rows changed anything: the power is still on, time still at 1 s.
  EXPECT_EQ(builder.row_count(), 1u);
  builder.append({.time_s = 1.0, .range_mm = 3001.0});
  builder.append({.time_s = 2.0, .power = false});
  EXPECT_EQ(append_error(builder, {.time_s = 3.0, .range_mm = 3002.0}).source(), "appended row 4");
}

TEST(MeasurementTableBuilder, MetadataMustReadBackAsItself) {
  MeasurementTableBuilder builder;
  builder.add_metadata("target", "wall, 3 m: grey");
  EXPECT_THROW(builder.add_metadata("a:b", "c"), MeasuredDataFileError);
  EXPECT_THROW(builder.add_metadata("key", "line\nbreak"), MeasuredDataFileError);
  EXPECT_EQ(builder.finish().metadata.size(), 1u);
}

TEST(MeasurementTableBuilder, BuiltTableReadsBackTheSame) {
  MeasurementTableBuilder builder;
  builder.add_metadata("sensor", "LMS200");
  for (int scan = 0; scan < 50; ++scan) {
    const double time = scan / 75.0;
    if (scan % 10 == 0) builder.append({.time_s = time, .case_temp_c = 22.0 + scan / 16.0});
    if (scan == 20) builder.append({.time_s = time, .power = false});
    if (scan == 30) builder.append({.time_s = time, .power = true});
    if (scan >= 20 && scan < 30) continue;
    for (int beam = 0; beam < 3; ++beam) {
      builder.append({.time_s = time,
                      .range_mm = 3000.0 + 0.1 * scan,
                      .beam = beam,
                      .true_range_mm = scan == 0 ? std::optional<double>(3000.0) : std::nullopt});
    }
  }
  const MeasurementTable table = builder.finish();
  const std::string text = testing::write(table);
  testing::expect_same_table(table, testing::parse(text));
}

}  // namespace
}  // namespace tofcomp::io
