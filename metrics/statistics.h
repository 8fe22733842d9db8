#pragma once
#include <vector>

namespace fscil {

double mean_of(const std::vector<double>& values);
// Sample standard deviation (n - 1); 0 for fewer than two values.
double standard_deviation_of(const std::vector<double>& values);

}  // namespace fscil
