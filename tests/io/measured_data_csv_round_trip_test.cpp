// Writing the interchange CSV: read → write → read gives back every value bit for bit, a second
// write is byte-identical, the writer refuses tables the reader would refuse, files are replaced
// atomically, and a daemon-sized file reads in one linear pass.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <random>

#include "measured_data_csv_test_support.hpp"

namespace tofcomp::io {
namespace {

using testing::expect_same_table;
using testing::parse;
using testing::write;

// Doubles whose text form is easy to get wrong: not exact in binary, the extremes of the range,
// a negative zero, many significant digits.
const std::vector<double> kAwkwardDoubles = {0.1,
                                             1e-300,
                                             22.0625,
                                             -0.0,
                                             0.0,
                                             1.0 / 3.0,
                                             2997.0,
                                             -123.456,
                                             1e21,
                                             123456789.125,
                                             std::numeric_limits<double>::denorm_min(),
                                             std::numeric_limits<double>::min(),
                                             std::numeric_limits<double>::max(),
                                             -std::numeric_limits<double>::max(),
                                             std::numeric_limits<double>::epsilon()};

const std::vector<double> kAwkwardRanges = {0.1,
                                            1e-300,
                                            -0.0,
                                            0.0,
                                            1.0 / 3.0,
                                            2997.0,
                                            81910.0,
                                            std::numeric_limits<double>::denorm_min(),
                                            std::numeric_limits<double>::min(),
                                            std::numeric_limits<double>::epsilon()};

// A table as a recording could hold one: columns in a random order with unknown ones among
// them, time ties, power switching with no range while off, beams, holding true ranges.
MeasurementTable random_table(std::uint64_t seed) {
  std::mt19937_64 random(seed);
  const auto chance = [&](double p) { return std::bernoulli_distribution(p)(random); };
  const auto number = [&] {
    if (chance(0.3)) return kAwkwardDoubles[random() % kAwkwardDoubles.size()];
    return std::uniform_real_distribution<double>(-5000.0, 5000.0)(random);
  };
  // Ranges and reference distances within what an LMS 200 reports (0 to 81910 mm), awkward
  // ones among them.
  const auto range = [&] {
    if (chance(0.3)) return kAwkwardRanges[random() % kAwkwardRanges.size()];
    return std::uniform_real_distribution<double>(0.0, 8191.0)(random);
  };
  const auto reference = [&] {
    const double r = range();
    return r > 0.0 ? r : 3000.0;
  };
  MeasurementTable table;
  table.metadata = {{"sensor", "LMS200"}, {"seed", std::to_string(seed)}, {"note", ""}};
  table.columns = {"time_s",    "range_mm",      "beam",     "case_temp_c", "power",
                   "ambient_c", "true_range_mm", "operator", "comment"};
  std::shuffle(table.columns.begin(), table.columns.end(), random);
  const std::vector<std::string> words = {"", "ann", " padded ", "x;y", "\"quoted\"", "1e3"};
  double time = chance(0.5) ? -0.0 : number() / 1000.0;
  bool power = true;
  for (int r = 0; r < 400; ++r) {
    if (chance(0.7)) time += chance(0.2) ? kAwkwardDoubles[random() % 6] : 1.0 / 75.0;
    MeasurementRow row;
    row.time_s = time;
    if (chance(0.1)) {
      power = !power;
      row.power = power;
    } else if (chance(0.05)) {
      row.power = power;  // repeating the power in force
    }
    if (power && chance(0.6)) row.range_mm = range();
    if (chance(0.5)) row.beam = static_cast<int>(random() % 361);
    if (chance(0.2)) row.case_temp_c = number();
    if (chance(0.1)) row.ambient_c = number();
    if (chance(0.1)) row.true_range_mm = reference();
    row.unknown_cells = {words[random() % words.size()], words[random() % words.size()]};
    table.rows.push_back(row);
  }
  return table;
}

TEST(MeasuredDataCsvRoundTrip, FormatDocumentExampleWritesShortestNumbers) {
  const MeasurementTable t = parse(
      "# sensor: LMS200\n# target: white board, 3 m\n"
      "time_s,range_mm,case_temp_c,power,ambient_c,true_range_mm\n"
      "0.000,,22.0000,1,22.00,\n0.000,2997,,,,3000\n0.250,3001,,,,\n0.500,2996,,,,\n"
      "1.000,,22.0625,,22.01,\n");
  EXPECT_EQ(write(t),
            "# sensor: LMS200\n"
            "# target: white board, 3 m\n"
            "time_s,range_mm,case_temp_c,power,ambient_c,true_range_mm\n"
            "0,,22,1,22,\n"
            "0,2997,,,,3000\n"
            "0.25,3001,,,,\n"
            "0.5,2996,,,,\n"
            "1,,22.0625,,22.01,\n");
}

TEST(MeasuredDataCsvRoundTrip, AwkwardDoublesSurviveBitForBit) {
  MeasurementTable table;
  table.columns = {"time_s", "case_temp_c"};
  for (const double value : kAwkwardDoubles) table.rows.push_back({.case_temp_c = value});
  const std::string text = write(table);
  EXPECT_NE(text.find("\n0,0.1\n0,1e-300\n0,22.0625\n0,-0\n"), std::string::npos) << text;
  const MeasurementTable back = parse(text);
  expect_same_table(table, back);
  EXPECT_EQ(write(back), text);
}

TEST(MeasuredDataCsvRoundTrip, RandomTablesAreLosslessAndRewriteByteIdentical) {
  for (std::uint64_t seed = 1; seed <= 25; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const MeasurementTable table = random_table(seed);
    const std::string first = write(table);
    const MeasurementTable back = parse(first);
    expect_same_table(table, back);
    for (std::size_t r = 0; r < back.rows.size(); ++r) {
      ASSERT_EQ(back.rows[r].line, static_cast<long>(table.metadata.size() + 2 + r));
    }
    EXPECT_EQ(write(back), first);
  }
}

TEST(MeasuredDataCsvRoundTrip, ForeignFileRewritesToAFixedPoint) {
  // CRLF, blank rows, padded cells, redundant digits: the first write normalizes, the second
  // changes nothing.
  const MeasurementTable t = parse(
      "\xEF\xBB\xBF#sensor:LMS200\r\n\r\ntime_s , range_mm,power,tag\r\n"
      "0.000, 2997.50 ,1, a \r\n,,,\r\n0.0100,,0,\r\n");
  const std::string first = write(t);
  EXPECT_EQ(first, "# sensor: LMS200\ntime_s,range_mm,power,tag\n0,2997.5,1, a \n0.01,,0,\n");
  EXPECT_EQ(write(parse(first)), first);
}

MeasuredDataFileError write_error(const MeasurementTable& table, std::string* written = nullptr) {
  std::ostringstream out;
  try {
    write_measured_data(out, table, "out.csv");
  } catch (const MeasuredDataFileError& error) {
    if (written) *written = out.str();
    return error;
  }
  ADD_FAILURE() << "no error; wrote:\n" << out.str();
  return MeasuredDataFileError("", 0, "", "");
}

TEST(MeasuredDataWriterChecks, RefusesWhatTheReaderWouldRefuse) {
  MeasurementTable table;
  table.metadata = {{"sensor", "LMS200"}};
  table.columns = {"time_s", "range_mm", "power"};
  table.rows = {{.time_s = 0.0, .range_mm = 1.0},
                {.time_s = 1.0, .power = false},
                {.time_s = 2.0, .range_mm = 2.0}};
  std::string written;
  const MeasuredDataFileError off = write_error(table, &written);
  EXPECT_EQ(off.line(), 5);
  EXPECT_EQ(off.column(), "range_mm");
  // The stream holds the rows before it, a file the reader accepts.
  EXPECT_EQ(parse(written).rows.size(), 2u);

  table.rows = {{.time_s = 1.0}, {.time_s = 0.0}};
  EXPECT_EQ(write_error(table).column(), "time_s");
  table.rows = {{.time_s = 0.0, .range_mm = std::numeric_limits<double>::quiet_NaN()}};
  EXPECT_EQ(write_error(table).column(), "range_mm");
  table.rows = {{.time_s = std::numeric_limits<double>::infinity()}};
  EXPECT_EQ(write_error(table).column(), "time_s");
}

TEST(MeasuredDataWriterChecks, RefusesValuesTheHeaderHasNoColumnFor) {
  MeasurementTable table;
  table.columns = {"time_s", "range_mm"};
  table.rows = {{.time_s = 0.0, .range_mm = 1.0, .case_temp_c = 22.0}};
  const MeasuredDataFileError error = write_error(table);
  EXPECT_EQ(error.line(), 2);
  EXPECT_EQ(error.column(), "case_temp_c");
  table.rows = {{.time_s = 0.0, .beam = 3}};
  EXPECT_EQ(write_error(table).column(), "beam");
}

TEST(MeasuredDataWriterChecks, RefusesTextThatWouldNotReadBack) {
  MeasurementTable table;
  table.columns = {"time_s", "note"};
  table.rows = {{.time_s = 0.0, .unknown_cells = {"a,b"}}};
  EXPECT_EQ(write_error(table).column(), "note");
  table.rows = {{.time_s = 0.0, .unknown_cells = {"two\nlines"}}};
  EXPECT_EQ(write_error(table).column(), "note");
  table.rows = {{.time_s = 0.0}};  // no cell for the unknown column
  EXPECT_NE(write_error(table).reason().find("0 cells of unknown columns"), std::string::npos);

  table.rows.clear();
  std::string written;
  for (const MetadataLine& bad : std::vector<MetadataLine>{
           {"a:b", "c"}, {"key", "two\nlines"}, {" key", "v"}, {"key", "v "}}) {
    table.metadata = {{"fine", "yes"}, bad};
    const MeasuredDataFileError error = write_error(table, &written);
    EXPECT_EQ(error.line(), 2) << bad.key;
    EXPECT_EQ(written, "") << "nothing is written before the header is known good";
  }
  table.metadata.clear();
  for (const auto& columns : std::vector<std::vector<std::string>>{{"range_mm"},
                                                                   {"time_s", "time_s"},
                                                                   {"time_s", ""},
                                                                   {"#x", "time_s"},
                                                                   {"time_s", "a,b"},
                                                                   {"time_s", " padded"}}) {
    table.columns = columns;
    EXPECT_EQ(write_error(table).line(), 1);
  }
}

TEST(MeasuredDataCsvFile, WrittenAtomicallyAndReadBack) {
  const std::filesystem::path dir =
      std::filesystem::path(::testing::TempDir()) / "measured_data_csv_file";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::filesystem::path file = dir / "run.csv";

  const MeasurementTable table = random_table(99);
  write_measured_data_file(file, table);
  expect_same_table(table, read_measured_data_file(file));

  MeasurementTable bad = table;
  bad.rows.back().time_s = -1e9;  // the last row goes back in time
  EXPECT_THROW(write_measured_data_file(file, bad), MeasuredDataFileError);
  expect_same_table(table, read_measured_data_file(file));  // the old file, whole
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), {}), 1)
      << "no temporary file left behind";

  EXPECT_THROW(write_measured_data_file(dir / "missing" / "run.csv", table), core::Error);
  std::filesystem::remove_all(dir);
}

// A recording of daemon size: 361 beams per scan, a temperature reading every 75 scans, the
// true ranges set on the first scan and holding. Times go in quarter seconds so that their text
// is made here in the writer's own form: writing what was read must give the text back.
TEST(MeasuredDataCsvLarge, DaemonSizedRecordingInOnePass) {
  constexpr int kBeams = 361;
  constexpr int kScans = 1500;  // 20 s: 541,500 ranges
  std::string text = "# sensor: LMS200\ntime_s,range_mm,beam,case_temp_c,true_range_mm\n";
  for (int scan = 0; scan < kScans; ++scan) {
    const std::string time = std::to_string(scan / 4) + (scan % 4 == 0   ? ""
                                                         : scan % 4 == 1 ? ".25"
                                                         : scan % 4 == 2 ? ".5"
                                                                         : ".75");
    if (scan % 75 == 0) text += time + ",,," + std::to_string(20 + scan / 75) + ",\n";
    for (int beam = 0; beam < kBeams; ++beam) {
      text += time + "," + std::to_string(3000 + (scan + beam) % 7) + "," + std::to_string(beam) +
              ",," + (scan == 0 ? std::to_string(3000 + beam) : "") + "\n";
    }
  }
  const MeasurementTable table = parse(text);
  ASSERT_EQ(table.rows.size(), static_cast<std::size_t>(kScans * kBeams + kScans / 75));
  EXPECT_EQ(table.rows.back().beam, kBeams - 1);
  EXPECT_EQ(write(table), text);
}

}  // namespace
}  // namespace tofcomp::io
