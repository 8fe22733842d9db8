#include "tools/fscil-bench/options/byte_size.h"

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <cstdlib>

#include "core/shown_text.h"
#include "core/error.h"
#include "core/number_text.h"

namespace fscil {

std::int64_t parse_byte_size(const std::string& text, const std::string& option) {
  const auto refuse = [&] {
    return CliError(fmt::format("{} '{}': expected a size such as 4G, 512M or 4294967296 (bytes; K, M, G, T are "
                                "powers of 1024), above 0 and at most 1024T",
                                option, shown_text(text)));
  };
  std::size_t digits = 0;
  while (digits < text.size() && (std::isdigit(static_cast<unsigned char>(text[digits])) || text[digits] == '.')) {
    ++digits;
  }
  const std::string number = text.substr(0, digits);
  std::string unit = text.substr(digits);
  if (number.empty() || number.front() == '.' || number.back() == '.') throw refuse();
  const auto parsed = parse_finite_number(number);
  if (!parsed) throw refuse();
  const double value = *parsed;

  for (char& c : unit) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  int power = 0;
  if (!unit.empty() && unit != "B") {
    const std::string prefixes = "KMGT";
    const auto at = prefixes.find(unit.front());
    if (at == std::string::npos) throw refuse();
    power = static_cast<int>(at) + 1;
    const std::string rest = unit.substr(1);
    if (!rest.empty() && rest != "B" && rest != "I" && rest != "IB") throw refuse();
  }
  if (power == 0 && number.find('.') != std::string::npos) throw refuse();  // a fraction of a byte
  const double bytes = std::floor(value * std::pow(1024.0, power));
  if (!(bytes >= 1) || bytes > std::pow(1024.0, 5)) throw refuse();
  return static_cast<std::int64_t>(bytes);
}

}  // namespace fscil
