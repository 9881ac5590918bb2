#include "io/measurement_columns.hpp"

namespace tofcomp::io {

std::string_view column_name(MeasurementColumn column) {
  switch (column) {
    case MeasurementColumn::Time:
      return "time_s";
    case MeasurementColumn::Range:
      return "range_mm";
    case MeasurementColumn::Beam:
      return "beam";
    case MeasurementColumn::CaseTemp:
      return "case_temp_c";
    case MeasurementColumn::Power:
      return "power";
    case MeasurementColumn::Ambient:
      return "ambient_c";
    case MeasurementColumn::TrueRange:
      return "true_range_mm";
  }
  return {};
}

std::optional<MeasurementColumn> measurement_column_named(std::string_view name) {
  for (const MeasurementColumn column : kMeasurementColumns) {
    if (column_name(column) == name) return column;
  }
  return std::nullopt;
}

bool has_cell(const MeasurementRow& row, MeasurementColumn column) {
  switch (column) {
    case MeasurementColumn::Time:
      return true;
    case MeasurementColumn::Range:
      return row.range_mm.has_value();
    case MeasurementColumn::Beam:
      return row.beam.has_value();
    case MeasurementColumn::CaseTemp:
      return row.case_temp_c.has_value();
    case MeasurementColumn::Power:
      return row.power.has_value();
    case MeasurementColumn::Ambient:
      return row.ambient_c.has_value();
    case MeasurementColumn::TrueRange:
      return row.true_range_mm.has_value();
  }
  return false;
}

}  // namespace tofcomp::io
