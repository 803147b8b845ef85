/// @file
/// @brief InstanceId: a process-wide serial number naming one object's contents, for caches keyed across calls
/// (RigidCcdCoherence). Unlike an address it is never reused: a new object at a freed object's address (a
/// per-step local, a pooled allocation) gets a new number, and so does a copy or an assigned-to object.
#pragma once

#include <atomic>
#include <cstdint>

namespace sdfccd {

class InstanceId {
 public:
  InstanceId() : m_value(next()) {}
  InstanceId(const InstanceId&) : m_value(next()) {}
  InstanceId& operator=(const InstanceId&) {
    m_value = next();  // the owner's contents change: a cache keyed by the old number must not match
    return *this;
  }
  std::uint64_t value() const { return m_value; }

 private:
  static std::uint64_t next() {
    static std::atomic<std::uint64_t> counter{0};
    return ++counter;  // starts at 1: 0 means "no identity"
  }
  std::uint64_t m_value;
};

}  // namespace sdfccd
