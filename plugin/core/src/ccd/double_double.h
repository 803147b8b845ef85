/// @file
/// @brief DoubleDouble: unevaluated sums hi + lo of two doubles (about 106 bits), for the few operations of
/// the long-segment clip (grid_field.cpp). Private to the core.
///
/// @details Dekker / Knuth error-free transformations: twoSum gives a + b exactly as hi + lo, twoProduct
/// (with fma) a * b exactly. Sums, products and quotients built on them are accurate to about 2^-104
/// relative, enough to locate the part of a 1e20-long segment inside a field's box to far below a cell.
#pragma once

#include <cmath>

namespace sdfccd::detail {

struct DoubleDouble {
  double hi = 0.0;
  double lo = 0.0;
  double value() const { return hi + lo; }  ///< rounded to the nearest double (up to a tie)
};

inline DoubleDouble twoSum(double a, double b) {
  const double s = a + b;
  const double bb = s - a;
  return {s, (a - (s - bb)) + (b - bb)};
}

inline DoubleDouble fastTwoSum(double a, double b) {  // |a| >= |b|
  const double s = a + b;
  return {s, b - (s - a)};
}

inline DoubleDouble twoProduct(double a, double b) {
  const double p = a * b;
  return {p, std::fma(a, b, -p)};
}

inline DoubleDouble operator+(const DoubleDouble& a, const DoubleDouble& b) {
  const DoubleDouble s = twoSum(a.hi, b.hi);
  const DoubleDouble t = twoSum(a.lo, b.lo);
  const DoubleDouble u = fastTwoSum(s.hi, s.lo + t.hi);
  return fastTwoSum(u.hi, u.lo + t.lo);
}

inline DoubleDouble operator-(const DoubleDouble& a) {
  return {-a.hi, -a.lo};
}
inline DoubleDouble operator-(const DoubleDouble& a, const DoubleDouble& b) {
  return a + (-b);
}

inline DoubleDouble operator*(const DoubleDouble& a, const DoubleDouble& b) {
  const DoubleDouble p = twoProduct(a.hi, b.hi);
  return fastTwoSum(p.hi, p.lo + (a.hi * b.lo + a.lo * b.hi));
}

/// Long division: three double quotients, each correcting the remainder of the previous ones.
inline DoubleDouble operator/(const DoubleDouble& a, const DoubleDouble& b) {
  const double q1 = a.hi / b.hi;
  DoubleDouble r = a - b * DoubleDouble{q1, 0.0};
  const double q2 = r.hi / b.hi;
  r = r - b * DoubleDouble{q2, 0.0};
  const double q3 = r.hi / b.hi;
  return fastTwoSum(q1, q2) + DoubleDouble{q3, 0.0};
}

inline bool operator<(const DoubleDouble& a, const DoubleDouble& b) {
  return a.hi < b.hi || (a.hi == b.hi && a.lo < b.lo);
}

}  // namespace sdfccd::detail
