#include "core/number_text.h"

#include <charconv>
#include <cmath>

namespace fscil {

template <typename T>
std::optional<T> parse_number(std::string_view text) {
  const char* first = text.data();
  const char* last = text.data() + text.size();
  // from_chars takes '-' but not '+'; "+-1" stays refused.
  if (first != last && *first == '+' && last - first > 1 && first[1] != '-') ++first;
  if (first == last) return std::nullopt;
  T value{};
  const auto [end, error] = std::from_chars(first, last, value);
  if (error != std::errc() || end != last) return std::nullopt;
  return value;
}

template std::optional<float> parse_number<float>(std::string_view);
template std::optional<double> parse_number<double>(std::string_view);
template std::optional<int> parse_number<int>(std::string_view);
template std::optional<long> parse_number<long>(std::string_view);
template std::optional<long long> parse_number<long long>(std::string_view);
template std::optional<unsigned long> parse_number<unsigned long>(std::string_view);
template std::optional<unsigned long long> parse_number<unsigned long long>(std::string_view);

std::optional<double> parse_finite_number(std::string_view text) {
  const auto value = parse_number<double>(text);
  if (!value || !std::isfinite(*value)) return std::nullopt;
  return value;
}

}  // namespace fscil
