// One cell of the interchange CSV, text to value and back. Numbers are read by std::from_chars
// and written by std::to_chars in the shortest form that reads back to the same double, so a
// value survives any number of read/write cycles bit for bit (-0 included).
#pragma once

#include <string>
#include <string_view>

#include "io/measured_data_error.hpp"

namespace tofcomp::io {

// Without leading and trailing spaces and tabs.
std::string_view trim_blanks(std::string_view text);

// A finite double written whole: "12x", "", "nan", "inf" and "1e400" fail at `at`, naming `column`.
double parse_number_cell(std::string_view text, std::string_view column,
                         const MeasurementPlace& at);

// A non-negative integer that fits an int, digits only ("3.0" fails).
int parse_beam_cell(std::string_view text, const MeasurementPlace& at);

// "1" (on) or "0" (off), nothing else.
bool parse_power_cell(std::string_view text, const MeasurementPlace& at);

void append_number_cell(std::string& out, double value);
void append_beam_cell(std::string& out, int beam);
void append_power_cell(std::string& out, bool on);

}  // namespace tofcomp::io
