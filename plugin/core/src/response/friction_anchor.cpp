/// @file
/// @brief Stick–slip Coulomb anchors per shell point (see friction_anchor.h).
#include "sdfccd/response/friction_anchor.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "sdfccd/error.h"

namespace sdfccd {
namespace {

void checkNonNegative(double value, const char* name) {
  if (!(value >= 0.0) || !std::isfinite(value)) {
    throw Error(std::string("friction: ") + name + " must be non-negative and finite");
  }
}

}  // namespace

void FrictionSettings::validate() const {
  checkNonNegative(friction, "friction (mu)");
  checkNonNegative(tangentialStiffness, "tangentialStiffness");
  checkNonNegative(tangentialDamping, "tangentialDamping");
}

AnchorMatchResult FrictionAnchorTable::match(const std::vector<AnchorContact>& contacts) {
  beginMatch();
  for (const AnchorContact& contact : contacts) matchNext(contact.point, contact.entryInField);
  return endMatch();
}

void FrictionAnchorTable::beginMatch() {
  std::swap(m_previous, m_anchors);
  m_anchors.clear();
  m_cursor = 0;
  m_counts = AnchorMatchResult{};
  m_matching = true;
}

std::size_t FrictionAnchorTable::matchNext(int point, const Vec3& entryInField) {
  if (!m_matching) throw Error("FrictionAnchorTable::matchNext: call beginMatch() first");
  if (point < 0 || (!m_anchors.empty() && point <= m_anchors.back().point)) {
    throw Error("FrictionAnchorTable: contacts must be sorted by strictly increasing point index (got " +
                std::to_string(point) + ")");
  }
  // Last step's anchors below `point` are no longer in contact.
  while (m_cursor < m_previous.size() && m_previous[m_cursor].point < point) {
    ++m_cursor;
    ++m_counts.dropped;
  }
  if (m_cursor < m_previous.size() && m_previous[m_cursor].point == point) {
    m_anchors.push_back(m_previous[m_cursor++]);
    ++m_counts.kept;
  } else {
    m_anchors.push_back(FrictionAnchor{point, entryInField});
    ++m_counts.created;
  }
  return m_anchors.size() - 1;
}

AnchorMatchResult FrictionAnchorTable::endMatch() {
  if (!m_matching) throw Error("FrictionAnchorTable::endMatch: call beginMatch() first");
  m_counts.dropped += static_cast<int>(m_previous.size() - m_cursor);
  m_previous.clear();
  m_cursor = 0;
  m_matching = false;
  return m_counts;
}

void FrictionAnchorTable::throwIndexOutOfRange() {
  throw Error("FrictionAnchorTable::updateAnchor: index out of range");
}

const FrictionAnchor* FrictionAnchorTable::find(int point) const {
  const auto it = std::lower_bound(m_anchors.begin(), m_anchors.end(), point,
                                   [](const FrictionAnchor& a, int p) { return a.point < p; });
  return (it != m_anchors.end() && it->point == point) ? &*it : nullptr;
}

void FrictionAnchorTable::clear() {
  m_anchors.clear();
  m_previous.clear();
  m_cursor = 0;
  m_matching = false;
}

}  // namespace sdfccd
