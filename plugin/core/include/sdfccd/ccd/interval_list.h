/// @file
/// @brief IntervalList: the sub-intervals of a step where a point is in contact, sorted and disjoint.
///
/// @details A segment rarely enters the level set more than a few times, so the first kInline intervals live
/// inside the object and a query in a hot loop allocates nothing; more spill to the heap. Written by hand
/// because neither Eigen nor the standard library has a small-buffer vector.
#pragma once

#include <cstddef>
#include <vector>

#include "sdfccd/math_types.h"

namespace sdfccd {

class IntervalList {
 public:
  static constexpr std::size_t kInline = 4;

  std::size_t size() const { return m_size; }
  bool empty() const { return m_size == 0; }
  void clear() {
    m_size = 0;
    m_overflow.clear();
  }
  const Interval& operator[](std::size_t n) const { return n < kInline ? m_inline[n] : m_overflow[n - kInline]; }
  Interval& operator[](std::size_t n) { return n < kInline ? m_inline[n] : m_overflow[n - kInline]; }
  const Interval& back() const { return (*this)[m_size - 1]; }
  Interval& back() { return (*this)[m_size - 1]; }

  /// Appends [begin, end]; merges it into the last interval when they touch or overlap (begin <= last end).
  /// Intervals must be appended in increasing order of begin.
  void append(double begin, double end) {
    if (m_size > 0 && begin <= back().end) {
      if (end > back().end) back().end = end;
      return;
    }
    if (m_size < kInline) {
      m_inline[m_size] = {begin, end};
    } else {
      m_overflow.push_back({begin, end});
    }
    ++m_size;
  }

 private:
  Interval m_inline[kInline];
  std::vector<Interval> m_overflow;
  std::size_t m_size = 0;
};

}  // namespace sdfccd
