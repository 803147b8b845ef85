/// @file
/// @brief rigidCcd() and pointTreeNodeMayCollide() (paper Section 3.3; see rigid_ccd.h), instantiated for every
/// field type of field_interface.h (as FCL does: the public header declares, this file defines).
#include "sdfccd/ccd/rigid_ccd.h"

#include <mutex>
#include <unordered_map>
#include <utility>

#include "ccd/rigid_ccd_coherent.h"
#include "ccd/rigid_ccd_query.h"
#include "sdfccd/field/analytic_fields.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/field/polytope_fields.h"

namespace sdfccd {
namespace detail {

std::shared_ptr<const RigidCcdCoherence::TreeTables> rigidCcdTreeTables(const PointTree& tree) {
  // Keyed by instance id (never reused); weak, so the tables go with the last history of their tree. Only a
  // history's first query (or one after a reset) comes here: a lock is cheap at that rate.
  static std::mutex mutex;
  static std::unordered_map<std::uint64_t, std::weak_ptr<const RigidCcdCoherence::TreeTables>> registry;
  const std::lock_guard<std::mutex> lock(mutex);
  std::weak_ptr<const RigidCcdCoherence::TreeTables>& slot = registry[tree.instanceId()];
  if (std::shared_ptr<const RigidCcdCoherence::TreeTables> shared = slot.lock()) return shared;
  auto tables = std::make_shared<RigidCcdCoherence::TreeTables>();
  const int nodes = tree.nodeCount();
  tables->parent.assign(static_cast<std::size_t>(nodes), -1);
  tables->reachFromOrigin.resize(static_cast<std::size_t>(nodes));
  for (int n = 0; n < nodes; ++n) {
    tables->reachFromOrigin[n] = tree.center(n).norm() + tree.radius(n);
    for (int k = 0; k < tree.childCount(n); ++k) tables->parent[tree.firstChild(n) + k] = n;
  }
  slot = tables;
  if (registry.size() > 64) {  // forget the trees no history uses any more
    for (auto it = registry.begin(); it != registry.end();) it = it->second.expired() ? registry.erase(it) : ++it;
  }
  return tables;
}

}  // namespace detail

template <class Field>
void rigidCcd(const PointTree& tree, const Field& field, const Rigid& sdfFromShellStart, const Rigid& sdfFromShellEnd,
              const RigidCcdSettings& settings, RigidCcdResult& outResult) {
  outResult.clear();
  if (tree.nodeCount() == 0) return;
  const detail::RigidCcdQuery<Field> query(tree, field, sdfFromShellStart, sdfFromShellEnd, settings);
  query.run(outResult);
}

template <class Field>
bool rigidCcdCertifiedClear(const PointTree& tree, const Field& field, const Rigid& sdfFromShellStart,
                            const Rigid& sdfFromShellEnd, const RigidCcdSettings& settings, RigidCcdCoherence& history,
                            RigidCcdResult& outResult) {
  if constexpr (!detail::kCoherentField<Field>) {
    return false;
  } else {
    if (settings.earliestOnly || settings.cullLipschitz != 0.0 || !settings.useTree) return false;
    if (!detail::coherentFrontClear(history, tree, field, settings, sdfFromShellStart, sdfFromShellEnd)) return false;
    outResult.clear();
    outResult.stats.certified = static_cast<std::int64_t>(history.front.size());
    ++history.queries;
    return true;
  }
}

template <class Field>
void rigidCcd(const PointTree& tree, const Field& field, const Rigid& sdfFromShellStart, const Rigid& sdfFromShellEnd,
              const RigidCcdSettings& settings, RigidCcdCoherence& history, RigidCcdResult& outResult) {
  if (rigidCcdCertifiedClear(tree, field, sdfFromShellStart, sdfFromShellEnd, settings, history, outResult)) return;
  if constexpr (!detail::kCoherentField<Field>) {
    // No identity to key the history by (an address may be reused by another field): fresh, and forget.
    history.reset();
    rigidCcd(tree, field, sdfFromShellStart, sdfFromShellEnd, settings, outResult);
  } else if (settings.earliestOnly || settings.cullLipschitz != 0.0 || !settings.useTree) {
    rigidCcd(tree, field, sdfFromShellStart, sdfFromShellEnd, settings, outResult);
  } else {
    outResult.clear();
    if (tree.nodeCount() == 0) return;
    const detail::RigidCcdQuery<Field> query(tree, field, sdfFromShellStart, sdfFromShellEnd, settings);
    detail::CoherentQuery<Field> coherent(query, tree, field, settings, sdfFromShellStart, sdfFromShellEnd, history);
    coherent.run(outResult);
  }
}

template <class Field>
bool pointTreeNodeMayCollide(const PointTree& tree, const Field& field, int node, const Rigid& sdfFromShellStart,
                             const Rigid& sdfFromShellEnd, const RigidCcdSettings& settings) {
  if (node < 0 || node >= tree.nodeCount()) throw Error("pointTreeNodeMayCollide: node out of range");
  const detail::RigidCcdQuery<Field> query(tree, field, sdfFromShellStart, sdfFromShellEnd, settings);
  SegmentCcdResult scratch;
  RigidCcdStats stats;
  if (tree.isLeaf(node)) {
    std::vector<PointContact> contacts;
    query.queryPoint(tree.point(node), scratch, contacts, stats);
    return !contacts.empty();
  }
  double first = 0.0;
  return query.nodeMayCollide(node, 0.0, scratch, stats, first);
}

#define SDFCCD_INSTANTIATE_RIGID_CCD(Field)                                                                          \
  template void rigidCcd<Field>(const PointTree&, const Field&, const Rigid&, const Rigid&, const RigidCcdSettings&, \
                                RigidCcdResult&);                                                                    \
  template void rigidCcd<Field>(const PointTree&, const Field&, const Rigid&, const Rigid&, const RigidCcdSettings&, \
                                RigidCcdCoherence&, RigidCcdResult&);                                                \
  template bool rigidCcdCertifiedClear<Field>(const PointTree&, const Field&, const Rigid&, const Rigid&,            \
                                              const RigidCcdSettings&, RigidCcdCoherence&, RigidCcdResult&);         \
  template bool pointTreeNodeMayCollide<Field>(const PointTree&, const Field&, int, const Rigid&, const Rigid&,      \
                                               const RigidCcdSettings&);
SDFCCD_FOR_EACH_FIELD(SDFCCD_INSTANTIATE_RIGID_CCD)
SDFCCD_FOR_EACH_TRIANGLE_FIELD(SDFCCD_INSTANTIATE_RIGID_CCD)
#undef SDFCCD_INSTANTIATE_RIGID_CCD

}  // namespace sdfccd
