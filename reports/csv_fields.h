#pragma once
#include <string>

#include "core/csv_text.h"  // csv_lines, csv_fields: what a finite_number field comes from

namespace fscil {

// A finite number filling the whole field; ReportError "<where>: '<text>' is not a finite number".
double finite_number(const std::string& text, const std::string& where);

}  // namespace fscil
