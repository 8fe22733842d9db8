#pragma once
#include <vector>

namespace fscil {

double mean_of(const std::vector<double>& values);
// Sample standard deviation (n - 1); 0 for fewer than two values.
double standard_deviation_of(const std::vector<double>& values);
// The 97.5% quantile of Student's t with `degrees_of_freedom` (>= 1): tabulated to 30, then the
// Cornish-Fisher expansion around the normal quantile (error below 1e-4).
double student_t_975(int degrees_of_freedom);
// Half-width of the two-sided 95% confidence interval of the mean, t_{0.975, n-1} s / sqrt(n);
// 0 for fewer than two values.
double confidence_half_width_95(const std::vector<double>& values);

}  // namespace fscil
