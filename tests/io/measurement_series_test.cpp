// The holding rules as the series apply them: power holds until set again and is on before the
// first row that sets it; a true range holds per beam until set again; beam defaults to 0.
#include "io/measurement_series.hpp"

#include <gtest/gtest.h>

#include "measured_data_csv_test_support.hpp"

namespace tofcomp::io {
namespace {

using testing::parse;

TEST(MeasurementSeries, PowerHoldsUntilSetAgainAndIsOnBeforeTheFirst) {
  const MeasurementTable t = parse(
      "time_s,range_mm,power\n"
      "0,3000,\n"   // on by default: the range is accepted
      "1,,1\n"      // already on: no change
      "2,,0\n"      // off
      "3,,\n"       // nothing: still off (a row with time alone)
      "4,,0\n"      // already off: no change
      "5,3001,1\n"  // on again, in force for its own range
      "6,3002,\n"   // still on
      "7,,0\n");
  EXPECT_EQ(power_changes(t),
            (std::vector<core::PowerChange>{{2.0, false}, {5.0, true}, {7.0, false}}));
  EXPECT_EQ(beam_ranges(t, 0).time_s, (std::vector<double>{0.0, 5.0, 6.0}));
}

TEST(MeasurementSeries, PowerOffFromTheStart) {
  const MeasurementTable t = parse("time_s,power,case_temp_c\n0,0,21\n10,1,21.5\n");
  EXPECT_EQ(power_changes(t), (std::vector<core::PowerChange>{{0.0, false}, {10.0, true}}));
}

TEST(MeasurementSeries, TrueRangeHoldsPerBeamUntilSetAgain) {
  const MeasurementTable t = parse(
      "time_s,beam,range_mm,true_range_mm,power\n"
      "0,,2999,3000,\n"  // beam empty: beam 0, its truth set on its own row
      "0,1,1499,,\n"     // beam 1 has no truth yet
      "1,1,,1500,0\n"    // beam 1's truth set on a row without a range, power off
      "2,,,,1\n"
      "2,1,1501,,\n"      // beam 1: 1500 holds across the power cycle
      "2,0,3001,,\n"      // beam 0: 3000 holds, untouched by beam 1's truth
      "3,0,3101,3100,\n"  // beam 0's truth changes on this row
      "4,0,3099,,\n"
      "4,1,1502,,\n");
  const BeamRanges beam0 = beam_ranges(t, 0);
  EXPECT_EQ(beam0.time_s, (std::vector<double>{0.0, 2.0, 3.0, 4.0}));
  EXPECT_EQ(beam0.range_mm, (std::vector<double>{2999.0, 3001.0, 3101.0, 3099.0}));
  EXPECT_EQ(beam0.true_range_mm,
            (std::vector<std::optional<double>>{3000.0, 3000.0, 3100.0, 3100.0}));
  EXPECT_EQ(beam0.line, (std::vector<long>{2, 7, 8, 9}));

  const BeamRanges beam1 = beam_ranges(t, 1);
  EXPECT_EQ(beam1.range_mm, (std::vector<double>{1499.0, 1501.0, 1502.0}));
  EXPECT_EQ(beam1.true_range_mm,
            (std::vector<std::optional<double>>{std::nullopt, 1500.0, 1500.0}));
  EXPECT_EQ(beam1.line, (std::vector<long>{3, 6, 10}));

  const std::map<int, BeamRanges> all = ranges_by_beam(t);
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all.at(0).true_range_mm, beam0.true_range_mm);
  EXPECT_EQ(all.at(0).line, beam0.line);
  EXPECT_EQ(all.at(1).true_range_mm, beam1.true_range_mm);
  EXPECT_EQ(all.at(1).line, beam1.line);
}

TEST(MeasurementSeries, TemperaturesAtTheirOwnInstants) {
  const MeasurementTable t = parse(
      "time_s,range_mm,case_temp_c,ambient_c\n"
      "0,3000,22.5,21\n"
      "0.5,3001,,\n"
      "1,,22.5625,\n"
      "2,,,21.25\n");
  const TimedSamples temps = case_temperatures(t);
  EXPECT_EQ(temps.time_s, (std::vector<double>{0.0, 1.0}));
  EXPECT_EQ(temps.value, (std::vector<double>{22.5, 22.5625}));
  const TimedSamples ambient = ambient_temperatures(t);
  EXPECT_EQ(ambient.time_s, (std::vector<double>{0.0, 2.0}));
  EXPECT_EQ(ambient.value, (std::vector<double>{21.0, 21.25}));
}

TEST(MeasurementSeries, EmptyTable) {
  const MeasurementTable t = parse("time_s\n");
  EXPECT_TRUE(beam_ranges(t, 0).time_s.empty());
  EXPECT_TRUE(ranges_by_beam(t).empty());
  EXPECT_TRUE(case_temperatures(t).time_s.empty());
  EXPECT_TRUE(power_changes(t).empty());
}

}  // namespace
}  // namespace tofcomp::io
