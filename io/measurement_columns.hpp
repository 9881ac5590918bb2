// The columns the interchange CSV knows (../shared/docs/data-format.md), by name and by cell.
#pragma once

#include <array>
#include <optional>
#include <string_view>

#include "io/measurement_table.hpp"

namespace tofcomp::io {

// In the order of the format's column table, which is also the order a builder writes them.
enum class MeasurementColumn { Time, Range, Beam, CaseTemp, Power, Ambient, TrueRange };

inline constexpr std::array<MeasurementColumn, 7> kMeasurementColumns = {
    MeasurementColumn::Time,     MeasurementColumn::Range, MeasurementColumn::Beam,
    MeasurementColumn::CaseTemp, MeasurementColumn::Power, MeasurementColumn::Ambient,
    MeasurementColumn::TrueRange};

// "time_s", "range_mm", "beam", "case_temp_c", "power", "ambient_c", "true_range_mm".
std::string_view column_name(MeasurementColumn column);

// The known column of that name; nullopt for an unknown column.
std::optional<MeasurementColumn> measurement_column_named(std::string_view name);

// Whether the row has a value in that column (time_s: always).
bool has_cell(const MeasurementRow& row, MeasurementColumn column);

}  // namespace tofcomp::io
