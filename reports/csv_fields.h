#pragma once
#include <string>
#include <vector>

namespace fscil {

// The fields of one line of our CSV files (no quoting); a trailing separator gives an empty last field.
std::vector<std::string> split_fields(const std::string& line, char separator = ',');
// A finite number filling the whole field; ReportError "<where>: '<text>' is not a finite number".
double finite_number(const std::string& text, const std::string& where);

}  // namespace fscil
