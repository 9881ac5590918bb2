// libFuzzer target for the measured-data CSV reader (io/measured_data_csv.hpp): arbitrary bytes
// as a file. Properties checked besides "no crash, no hang, no sanitizer report": the only
// exception that leaves is MeasuredDataFileError (anything else ends the run), naming the source
// at the start of its message and a line no later than the input has; an accepted table keeps
// to the device's limits (ranges 0..81910 mm, reference distances more than 0 and at most
// 81910 mm), and written and read again it is the same table, its second writing byte for byte
// the first.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>
#include <string_view>

#include "core/lms200_limits.hpp"
#include "io/measured_data_csv.hpp"

namespace {

using namespace tofcomp::io;

void check(bool condition) {
  if (!condition) std::abort();
}

std::string written(const MeasurementTable& table) {
  std::ostringstream out;
  write_measured_data(out, table, "fuzz.csv");
  return out.str();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  MeasurementTable table;
  try {
    std::istringstream in(text);
    table = read_measured_data(in, "fuzz.csv");
  } catch (const MeasuredDataFileError& e) {
    check(std::string_view(e.what()).starts_with("fuzz.csv"));
    const long lines = 1 + static_cast<long>(std::count(text.begin(), text.end(), '\n'));
    check(e.line() >= 1 && e.line() <= lines + 1);
    return 0;
  } catch (...) {
    std::abort();
  }
  for (const MeasurementRow& row : table.rows) {
    check(std::isfinite(row.time_s));
    if (row.range_mm) {
      check(*row.range_mm >= 0.0 && *row.range_mm <= tofcomp::core::lms200::kMaxRangeMm);
    }
    if (row.true_range_mm) {
      check(*row.true_range_mm > 0.0 && *row.true_range_mm <= tofcomp::core::lms200::kMaxRangeMm);
    }
  }
  const std::string first = written(table);
  std::istringstream again(first);
  const MeasurementTable reread = read_measured_data(again, "fuzz.csv");
  check(reread.rows.size() == table.rows.size());
  check(written(reread) == first);
  return 0;
}
