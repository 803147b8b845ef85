/// @file
/// @brief DeferredQueries: one step's CCD queries, planned serially, computed together on the pool, consumed
/// serially in Bullet's pair order (see step/step_planner.cpp for the why).
///
/// @details A query is keyed by (the pair's manifold, the role's index in the pair): both are stable through a
/// step, and one algorithm processes its pair once per step. A query's closure holds copies of everything it
/// reads that Bullet or the narrowphase might change (poses, velocities, settings) and pointers only to what
/// stays put during the step (the model's tree and field, the pair and role's anchor table and CCD history,
/// which only this query touches; penalty mode also the bodies' predicted motions in the step's BodySteps,
/// which planning reserves and nothing writes during the batch, and the world's settings). Results are kept across
/// steps so their buffers are reused.
#pragma once

#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <type_traits>
#include <unordered_map>
#include <vector>

#include "../step/contact_record.h"  // by its own path: the white-box tests include this header from outside
#include "sdfccd/field/analytic_fields.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/response/contact_query.h"
#include "sdfccd/response/contact_reduction.h"

namespace sdfccd::bullet::detail {

class NarrowphasePool;

/// The fields a deferred query may hold: our model's grid field (persistent, by address) and a ground plane
/// (built per step, by value). Other fields (convex shapes' cached hulls, mesh triangles near a body) are built
/// or cached while the narrowphase runs: their roles stay serial.
template <class Field>
constexpr bool kDeferrableField = std::is_same_v<Field, GridField> || std::is_same_v<Field, PlaneField>;

/// What a deferred query keeps of its field.
template <class Field>
struct HeldField {
  HeldField() = default;  // null until assigned (DeferredQueries::slot)
  explicit HeldField(const Field& field) : pointer(&field) {}
  const Field& get() const { return *pointer; }
  const Field* pointer = nullptr;
};
template <>
struct HeldField<PlaneField> {
  HeldField() : value(PlaneField::ground()) {}  // a placeholder until assigned (DeferredQueries::slot)
  explicit HeldField(const PlaneField& field) : value(field) {}
  const PlaneField& get() const { return value; }
  PlaneField value;
};

/// One role's work that touches no Bullet object: the query and what is computed from it (penalty_role.h,
/// solver_role.cpp). The stepping thread then applies it (statistics, manifold points, impulses, records).
struct RoleResult {
  // What every role writes comes first (a result is written a step after its last use, into cold cache lines:
  // a role without contacts writes the first two lines).
  double roleScale = 1.0;      // s_r of the role (penalty mode's contact load)
  bool ground = false;         // the field is a plane (the ground's statistics)
  bool hasRecord = false;      // the CCD found contacts: `record` holds the role's step
  double shadowSeconds = 0.0;  // the point-by-point repeat's CPU time (shadowLinearEvery), 0 when none ran
  // Penalty mode: what the stepping thread reads of the role's query (penalty_role.h). The query itself is
  // computed in the thread's own result and stays there, warm for the thread's next query (its ~600 bytes
  // written here missed the cache at every role).
  struct PenaltySummary {
    double ccdSeconds = 0.0;  // queryContacts' clocks (ContactQueryResult)
    double penaltySeconds = 0.0;
    std::int64_t segmentQueries = 0;        // the CCD's (RigidCcdStats)
    bool touched = false;                   // the CCD found contacts
    PairResponseCoefficients coefficients;  // the per-area law's caps (the contact load, softenedPairs)
  };
  PenaltySummary penalty;
  // Penalty mode: the deepest points at the step's end (world; normal on the manifold's convention, depth < 0).
  struct ManifoldPoint {
    Vec3 normal = Vec3::Zero();
    Vec3 point = Vec3::Zero();
    double depth = 0.0;
  };
  std::vector<ManifoldPoint> manifoldPoints;
  ContactQueryResult query;  // solver mode: the CCD in `ccd`, `ccdSeconds` (penalty mode: unused, see `penalty`)
  ContactRecord record;
  // Solver mode: the role's candidates at the step's start, with their rebound and solver distance.
  std::vector<ContactCandidate> candidates;
  std::vector<double> bounce;
  std::vector<double> distance;
  double margin = 0.0;  // the speculative margin (m)
};

class DeferredQueries {
 public:
  DeferredQueries() = default;
  DeferredQueries(const DeferredQueries&) = delete;
  DeferredQueries& operator=(const DeferredQueries&) = delete;

  /// An object of type Data kept until the next clear(), at an address that does not change meanwhile: a queued
  /// query holds a pointer to it instead of a copy of its inputs. The caller fills it in place (it holds whatever
  /// the last step left there: every field must be written), so queueing copies nothing twice and allocates
  /// nothing once the step's storage is there (it is reused from step to step).
  template <class Data>
  Data& slot() {
    Arena<Data>& arena = arenaOf<Data>();
    if (arena.used == arena.items.size()) arena.items.push_back(std::make_unique<Data>());
    return *arena.items[arena.used++];
  }
  /// A copy of `data` kept the same way (Data need not be default-constructible).
  template <class Data>
  const Data& stash(const Data& data) {
    Arena<Data>& arena = arenaOf<Data>();
    if (arena.used == arena.items.size()) {
      arena.items.push_back(std::make_unique<Data>(data));
    } else {
      *arena.items[arena.used] = data;
    }
    return *arena.items[arena.used++];
  }

  /// Writes one role's work (penalty_role.h; solver mode: solver_role.cpp).
  using Compute = std::function<void(RoleResult&)>;
  /// The same as a plain function of a slot(): `run(data, out)` (no std::function to build and move per query).
  using Run = void (*)(const void* data, RoleResult& out);

  /// Forgets the last step's queries (keeps the result buffers).
  void clear();
  /// Queues the query of (manifold, role). A key must be planned once per step (planStep walks each pair once;
  /// a duplicate would be computed, and which copy take() returns is not fixed). False when a streamed batch is
  /// full.
  bool add(const void* manifold, int role, Compute compute);
  /// The same with the work as run(data, out); `data` must stay put until the next clear() (a slot()).
  bool add(const void* manifold, int role, Run run, const void* data);
  std::size_t size() const { return m_jobs.size(); }
  /// Computes every query on `pool`, each into its own result.
  void runAll(NarrowphasePool& pool);
  /// A streamed batch: after begin(pool, capacity) every add() is computed on the pool as soon as it is queued
  /// (published in small groups), while the caller goes on planning; finish() computes the rest and returns when
  /// all are done. At most `capacity` queries are streamed (the buffers must not move while workers read them);
  /// add() refuses more (false: the role is computed when Bullet reaches it). finish() must be called.
  void begin(NarrowphasePool& pool, std::size_t capacity);
  void finish();
  /// The result of (manifold, role), valid until the next clear(); null when there is none, or it was taken
  /// already. Rethrows what the query threw, where the serial narrowphase would have thrown it.
  const RoleResult* take(const void* manifold, int role);
  /// Is the query after the last one taken another role of `manifold`? A pair's roles are queued one after the
  /// other, so a caller taking them in order stops here without looking up a role that is not there (a miss costs
  /// a hashed lookup, and the first of a step builds the hashed index).
  bool nextIsOf(const void* manifold) const {
    return m_cursor < m_jobs.size() && m_jobs[m_cursor].key.manifold == manifold;
  }
  /// Was (manifold, role) planned this step, and not taken yet?
  bool pending(const void* manifold, int role);

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
  /// What the stepping thread writes per query (the workers only read it)...
  struct Job {
    Key key;
    Run run = nullptr;
    const void* data = nullptr;
    bool taken = false;
  };
  /// ...and what a worker writes: kept apart, so neither thread writes the other's cache lines.
  struct Outcome {
    RoleResult result;
    std::exception_ptr error;      // thrown on a worker: rethrown by take() on the stepping thread
    std::uint64_t generation = 0;  // the m_generation of the batch that computed it (stale otherwise)
  };
  struct ArenaBase {
    virtual ~ArenaBase() = default;
    std::size_t used = 0;
  };
  template <class Data>
  struct Arena : ArenaBase {
    std::vector<std::unique_ptr<Data>> items;  // the Data never move; only their pointers do
  };
  /// A process-wide index per stashed type.
  static std::size_t nextArenaIndex();
  template <class Data>
  Arena<Data>& arenaOf() {
    static const std::size_t index = nextArenaIndex();
    if (m_arenas.size() <= index) m_arenas.resize(index + 1);
    if (!m_arenas[index]) m_arenas[index] = std::make_unique<Arena<Data>>();
    return static_cast<Arena<Data>&>(*m_arenas[index]);
  }
  std::vector<std::unique_ptr<ArenaBase>> m_arenas;
  std::vector<Job> m_jobs;
  NarrowphasePool* m_streaming = nullptr;  // the pool of an open streamed batch
  std::size_t m_capacity = 0;
  std::function<void(std::size_t)> m_task;  // the batch's task (outlives it)
  std::vector<Outcome> m_results;           // m_results[i] belongs to m_jobs[i]; kept across steps (their buffers)
  std::uint64_t m_generation = 1;           // advanced by clear(): last step's outcomes are stale
  /// The job of `key`, or -1. Bullet takes the pairs in the order the plan walked them (its pair array), so the
  /// job after the last one found is tried first; the hashed index is built only when that guess fails.
  std::ptrdiff_t find(const Key& key);
  std::size_t m_cursor = 0;
  std::unordered_map<Key, std::size_t, KeyHash> m_index;  // built on the first failed guess of a step
  bool m_indexed = false;
};

}  // namespace sdfccd::bullet::detail
