/// @file
/// @brief LatestValue: the newest value one thread publishes for another to read (haptic <-> simulation loop).
///
/// @details The two haptic loops (paper Section 4.2, "two asynchronous loops") only ever need the newest
/// pose or force of the other loop; older ones may be dropped. Design choice: a mutex around one slot,
/// held only to copy a value of a few hundred bytes (well under a microsecond), never while computing.
/// A seqlock would avoid the lock, but in C++ it is only free of data races (and TSan-clean) when every
/// payload word is itself an atomic; at a 1 kHz reader and a few-kHz writer, the uncontended mutex costs
/// tens of nanoseconds and is correct by construction. The sequence number tells a reader whether the value is new.
///
/// Thread safety: any number of publishers and readers.
#pragma once

#include <cstdint>
#include <mutex>

namespace sdfccd::haptics {

template <class T>
class LatestValue {
 public:
  /// Replaces the value; returns its sequence number (1 for the first publish).
  std::uint64_t publish(const T& value) {
    std::lock_guard<std::mutex> lock(m_mutex);
    m_value = value;
    return ++m_sequence;
  }
  /// Copies the newest value into `out` and returns its sequence number (0: nothing published yet, `out`
  /// untouched).
  std::uint64_t read(T& out) const {
    std::lock_guard<std::mutex> lock(m_mutex);
    if (m_sequence != 0) out = m_value;
    return m_sequence;
  }
  std::uint64_t sequence() const {
    std::lock_guard<std::mutex> lock(m_mutex);
    return m_sequence;
  }

 private:
  mutable std::mutex m_mutex;
  T m_value{};
  std::uint64_t m_sequence = 0;
};

}  // namespace sdfccd::haptics
