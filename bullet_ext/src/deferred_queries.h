/// @file
/// @brief DeferredQueries: one step's CCD queries, planned serially, computed together on the pool, consumed
/// serially in Bullet's pair order (issue 17 item 1; see sdfccd_parallel_step.cpp for the why).
///
/// @details A query is keyed by (the pair's manifold, the role's index in the pair): both are stable through a
/// step, and one algorithm processes its pair once per step. A query's closure holds copies of everything it
/// reads that Bullet or the narrowphase might change (poses, velocities, settings) and pointers only to what
/// stays put during the step (the model's tree and field, the pair and role's anchor table and CCD history,
/// which only this query touches). Results are kept across steps so their buffers are reused.
#pragma once

#include <cstddef>
#include <exception>
#include <functional>
#include <type_traits>
#include <unordered_map>
#include <vector>

#include "sdfccd/field/analytic_fields.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/response/contact_query.h"

namespace sdfccd::detail {

class NarrowphasePool;

/// The fields a deferred query may hold: our model's grid field (persistent, by address) and a ground plane
/// (built per step, by value). Other fields (convex shapes' cached hulls, mesh triangles near a body) are built
/// or cached while the narrowphase runs: their roles stay serial.
template <class Field>
constexpr bool kDeferrableField = std::is_same_v<Field, GridField> || std::is_same_v<Field, PlaneField>;

/// What a deferred query keeps of its field.
template <class Field>
struct HeldField {
  explicit HeldField(const Field& field) : pointer(&field) {}
  const Field& get() const { return *pointer; }
  const Field* pointer;
};
template <>
struct HeldField<PlaneField> {
  explicit HeldField(const PlaneField& field) : value(field) {}
  const PlaneField& get() const { return value; }
  PlaneField value;
};

class DeferredQueries {
 public:
  /// Writes one query's result (penalty mode: queryContacts; solver mode: the CCD into `ccd` and `ccdSeconds`).
  using Compute = std::function<void(ContactQueryResult&)>;

  /// Forgets the last step's queries (keeps the result buffers).
  void clear();
  void add(const void* manifold, int role, Compute compute);
  std::size_t size() const { return m_jobs.size(); }
  /// Computes every query on `pool`, each into its own result.
  void runAll(NarrowphasePool& pool);
  /// Swaps the result of (manifold, role) into `out` (buffers circulate); false when there is none, or it was
  /// taken already. Rethrows what the query threw, where the serial narrowphase would have thrown it.
  bool take(const void* manifold, int role, ContactQueryResult& out);

 private:
  struct Key {
    const void* manifold;
    int role;
    bool operator==(const Key& other) const { return manifold == other.manifold && role == other.role; }
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      return std::hash<const void*>()(k.manifold) ^ (static_cast<std::size_t>(k.role) * 0x9e3779b97f4a7c15ull);
    }
  };
  struct Job {
    Compute compute;
    std::exception_ptr error;  // thrown on a worker: rethrown by take() on the stepping thread
    bool done = false;
    bool taken = false;
  };
  std::vector<Job> m_jobs;
  std::vector<ContactQueryResult> m_results;  // m_results[i] belongs to m_jobs[i]; kept across steps
  std::unordered_map<Key, std::size_t, KeyHash> m_index;
};

}  // namespace sdfccd::detail
