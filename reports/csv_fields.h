#pragma once
#include <string>
#include <vector>

namespace fscil {

// The lines of a CSV file as a spreadsheet may also save it: a byte-order mark before the first
// line and a carriage return before each line end are not part of any line.
std::vector<std::string> csv_lines(const std::string& text);
// The fields of one line of our CSV files (no quoting); a trailing separator gives an empty last field.
std::vector<std::string> split_fields(const std::string& line, char separator = ',');
// A finite number filling the whole field; ReportError "<where>: '<text>' is not a finite number".
double finite_number(const std::string& text, const std::string& where);

}  // namespace fscil
