#pragma once
#include <cstdint>
#include <optional>
#include <string_view>

namespace fscil {

// The one number parser. Reads the whole of `text` as a decimal number of type T (float, double,
// int, std::int64_t, std::uint64_t): an optional sign ('+' too), digits, and for floating point
// a fraction, an exponent, or inf/nan. Nothing else: no blanks around it, no hexadecimal, no
// trailing characters, no value outside T's range. The same in every locale. Callers decide what
// else a value must be (finite, in a range) and name the field in their error.
template <typename T>
std::optional<T> parse_number(std::string_view text);

extern template std::optional<float> parse_number<float>(std::string_view);
extern template std::optional<double> parse_number<double>(std::string_view);
extern template std::optional<int> parse_number<int>(std::string_view);
extern template std::optional<long> parse_number<long>(std::string_view);
extern template std::optional<long long> parse_number<long long>(std::string_view);
extern template std::optional<unsigned long> parse_number<unsigned long>(std::string_view);
extern template std::optional<unsigned long long> parse_number<unsigned long long>(std::string_view);

// parse_number<double> of a finite value, or nothing.
std::optional<double> parse_finite_number(std::string_view text);

}  // namespace fscil
