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
// The fewest seeds a 95% confidence interval or a test is reported from: with two, the interval's
// t quantile is 12.7 and the interval says nothing.
constexpr int kFewestSeedsForInference = 3;

// Two-sided p-value of Student's t statistic `t` with `degrees_of_freedom` (>= 1), from the
// regularized incomplete beta function.
double student_t_two_sided_p(double t, int degrees_of_freedom);
// The paired t-test of a[i] against b[i] (the same seeds): two-sided p of the mean difference
// being 0; 1 where the differences are all equal to 0, 0 where they are equal and not 0, NaN
// for fewer than two pairs.
double paired_t_test_p(const std::vector<double>& a, const std::vector<double>& b);
// Holm's step-down adjustment of p-values for testing them together (family-wise error).
std::vector<double> holm_adjusted(const std::vector<double>& p);

}  // namespace fscil
