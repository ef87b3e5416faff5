// Pearson's chi-square test of observed counts against expected counts, as pbrt-v4's tests do it:
// bins with expected count < 5 are merged, and the p-value comes from the regularized upper
// incomplete gamma function Q(dof / 2, chi2 / 2).
#pragma once

#include <cmath>
#include <cstdio>
#include <vector>

namespace meso::testing {

// Q(a, x) by series (x < a + 1) or Lentz's continued fraction (Numerical Recipes, 6.2).
inline double upperIncompleteGammaQ(double a, double x) {
  if (x <= 0.0) return 1.0;
  const double lnGammaA = std::lgamma(a);
  if (x < a + 1.0) {
    double sum = 1.0 / a, term = sum, ap = a;
    for (int n = 0; n < 10000; ++n) {
      ap += 1.0;
      term *= x / ap;
      sum += term;
      if (std::abs(term) < std::abs(sum) * 1e-15) break;
    }
    return 1.0 - sum * std::exp(-x + a * std::log(x) - lnGammaA);
  }
  double b = x + 1.0 - a, c = 1e300, d = 1.0 / b, h = d;
  for (int i = 1; i < 10000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < 1e-300) d = 1e-300;
    c = b + an / c;
    if (std::abs(c) < 1e-300) c = 1e-300;
    d = 1.0 / d;
    const double del = d * c;
    h *= del;
    if (std::abs(del - 1.0) < 1e-15) break;
  }
  return std::exp(-x + a * std::log(x) - lnGammaA) * h;
}

struct ChiSquareResult {
  double chi2 = 0.0;
  int dof = 0;
  double pValue = 1.0;
};

// Merges bins (in order) until each merged bin expects at least 5; dof = merged bins - 1.
inline ChiSquareResult chiSquareTest(const std::vector<double>& observed,
                                     const std::vector<double>& expected) {
  ChiSquareResult r;
  double obs = 0.0, exp = 0.0;
  int bins = 0;
  for (size_t i = 0; i < observed.size(); ++i) {
    obs += observed[i];
    exp += expected[i];
    if (exp >= 5.0) {
      r.chi2 += (obs - exp) * (obs - exp) / exp;
      ++bins;
      obs = exp = 0.0;
    }
  }
  if (exp > 0.0 || obs > 0.0) {  // the leftover joins the chi2 as one more bin
    r.chi2 += (obs - exp) * (obs - exp) / std::max(exp, 1e-12);
    ++bins;
  }
  r.dof = std::max(bins - 1, 1);
  r.pValue = upperIncompleteGammaQ(0.5 * r.dof, 0.5 * r.chi2);
  return r;
}

// Significance level per test for `tests` simultaneous tests at overall level alpha (Sidak).
inline double sidakAlpha(double alpha, int tests) {
  return 1.0 - std::pow(1.0 - alpha, 1.0 / tests);
}

inline void dumpTable(const std::vector<double>& observed, const std::vector<double>& expected) {
  for (size_t i = 0; i < observed.size(); ++i)
    std::fprintf(stderr, "  bin %3zu  observed %10.1f  expected %10.1f\n", i, observed[i],
                 expected[i]);
}

}  // namespace meso::testing
