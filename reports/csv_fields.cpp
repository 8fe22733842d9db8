#include "reports/csv_fields.h"

#include <fmt/format.h>

#include <cmath>

#include "core/shown_text.h"
#include "core/error.h"
#include "core/number_text.h"

namespace fscil {

double finite_number(const std::string& text, const std::string& where) {
  const auto value = parse_finite_number(text);
  if (!value) throw ReportError(fmt::format("{}: '{}' is not a finite number", where, shown_text(text)));
  return *value;
}

}  // namespace fscil
