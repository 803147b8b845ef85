/// @file
/// @brief SdfccdContactSystem: the continuous penalty contact of Section 4.1 inside Bullet's step, with
/// time-of-impact clamping against tunnelling; and registerSdfccdAlgorithms(), the one call that installs it.
///
/// @details Where each part runs in btDiscreteDynamicsWorld's step:
/// 1. Narrowphase (SdfccdCollisionAlgorithm -> processPair): for each pair, each body in each role (shell of
///    A vs field of B, then shell of B vs field of A; a btStaticPlaneShape is an analytic PlaneField and only
///    a field; a btBoxShape, btSphereShape or btCapsuleShape is an analytic field and points sampled on its
///    surface, so it takes both roles like ours, and so does any other btConvexShape; a triangle mesh or
///    terrain is its triangles near our body as a field and its vertices there as points: registerWith()),
///    the rigid CCD runs over the step's motion: start = the
///    body's current transform, end = its motion integrated over the step from the velocity *plus* the forces
///    Bullet will add (gravity and applied forces, the same symplectic Euler step integrateVelocities/
///    integrateTransforms perform), which is the actual end of the step because our contacts add no solver
///    rows. (getInterpolationWorldTransform at this point omits gravity: it is off by g dt^2.) The continuous
///    penalty model integrates impulse and angular impulse over the contact sub-intervals (eqs. 3-4) — or the
///    discrete model at the end pose. Both run in one core call, queryContacts (contact_query.h), on the
///    frames of the shell's body and of the field (the model's field frame in its body).
/// 2. The impulses I and M reach the velocities as impulses (eq. 5: the averaged force F* = I/dt acting over
///    a step is the impulse F* dt; forces applied with applyCentralForce would accumulate over substeps
///    until clearForces). When, is a setting (ForceTiming): the paper's "over the next step" (in
///    updateAction: this object is a btActionInterface, run after integrateTransforms), or at once in the
///    narrowphase, before Bullet integrates the same step (the default: stable at stiffer settings).
/// 3. Time-of-impact clamping (beyond the paper): averaged penalty forces act one step late and cannot stop a
///    fast body at a thin wall. When a shell point *entered* the contact set during the step (state Hit) and
///    either left it again before the step's end (it passed through) or ends deeper than
///    toiDepthCells cells, the pair "clamps": every dynamic body of the pair is moved back to its pose at the
///    earliest such first-hit fraction (translation lerped, rotation slerped along the step's motion), an
///    inelastic impulse at the first-contact point removes the approaching normal velocity, and the pair's
///    penalty impulses of that step are dropped. Resting and sliding contact (points that start inside, or
///    shallow entries) are left to the penalty forces. Only the continuous model clamps: the discrete model
///    is the baseline and may tunnel.
/// Contacts are visible to users as manifold points (at most 4 per pair, the deepest at the step's end,
/// normal on B, negative distance) and through lastStepContacts(). The solver never answers them twice: our
/// manifolds get a contact processing threshold of -BT_LARGE_FLOAT, and Bullet's solvers only turn points
/// with distance <= that threshold into constraints.
/// Sleeping, the Bullet way: a body that is not active is at rest with infinite mass for the step (no impulse,
/// no activate()); Bullet's island manager wakes it when its island has an active member.
/// Kinematic bodies are moving bodies of infinite mass: their velocity counts, the clamp never rewinds or drops
/// their pairs (time_of_impact_clamp.h). Compound children each get their own pose (motion_prediction.h).
///
/// Thread safety: one system per world; Bullet's narrowphase must be single threaded (btDiscreteDynamicsWorld,
/// not btDiscreteDynamicsWorldMt: registration refuses the Mt world and dispatcher). Models are shared read-only.
/// Inside the step the CCD of our pairs runs on our own pool (SdfccdContactSettings::threads), touching no Bullet
/// object; Bullet sees the results serially, in its pair order (sdfccd_parallel_step.cpp).
/// Ownership: see registerSdfccdAlgorithms() at the end of this file.
#pragma once

#include <BulletDynamics/Dynamics/btActionInterface.h>

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <unordered_map>
#include <vector>

#include "sdfccd/ccd/rigid_ccd.h"
#include "sdfccd/field/polytope_fields.h"
#include "sdfccd/math_types.h"
#include "sdfccd/response/contact_mode.h"
#include "sdfccd/response/contact_query.h"
#include "sdfccd/response/contact_reduction.h"
#include "sdfccd/response/force_timing.h"
#include "sdfccd/response/friction_anchor.h"
#include "sdfccd/response/penalty_model.h"
#include "sdfccd/response/time_of_impact_clamp.h"
#include "sdfccd/shell/point_tree.h"

class btCollisionDispatcher;
class btCollisionObject;
class btCollisionObjectWrapper;
class btCollisionShape;
class btCollisionAlgorithmCreateFunc;
class btCollisionWorld;
class btDiscreteDynamicsWorld;
class btManifoldResult;
class btPersistentManifold;
class btDispatcher;
template <typename T>
class btAlignedObjectArray;
typedef btAlignedObjectArray<btPersistentManifold*> btManifoldArray;
struct btDispatcherInfo;

namespace sdfccd {

class SdfccdShape;
namespace detail {
class ConvexShapeCache;
class DeferredQueries;
class NarrowphasePool;
struct ContactRecord;
struct RoleResult;
template <class Body>
struct PenaltyRoleFacts;
}  // namespace detail

/// Receives one line of text: an unsupported pair's announcement (SdfccdContactSystem::setLogCallback).
using SdfccdLogCallback = std::function<void(const std::string& line)>;

struct SdfccdSolverPair;

/// Settings of the contact model, shared by every pair of one world.
/// The most narrowphase threads a contact system accepts (SdfccdContactSettings::threads, `--threads`).
inline constexpr int kMaxNarrowphaseThreads = 1024;

struct SdfccdContactSettings {
  /// Penalty (the paper's model) or Solver (speculative manifold points answered by Bullet's solver; see
  /// solver_contacts.cpp). Solver by default: on the 20-bunny drop it has the larger stable step at a lower cost
  /// (`sdfccd bench bullet --part modes,stable`; docs/bullet.md, docs/benchmarks.md).
  SdfccdContactMode mode = SdfccdContactMode::Solver;
  /// Solver mode: CCD level set and speculative reach, in cells of the field, capped at maxSpeculativeMargin.
  double speculativeMarginCells = 0.5;
  double maxSpeculativeMargin = 0.002;              ///< m (model units)
  ForceTiming forceTiming = ForceTiming::SameStep;  ///< see ForceTiming
  /// Model (continuous/discrete), stiffness per area (or per point), damping ratio (or per point), direction,
  /// friction law; new worlds get PenaltySettings::trustworthy().
  PenaltySettings penalty = PenaltySettings::trustworthy();
  bool timeOfImpactClamp = true;         ///< continuous model only: clamp bodies at first hits (see file comment)
  double toiDepthCells = 0.5;            ///< clamp when an entering point ends deeper than this (field cells)
  bool useTree = true;                   ///< point tree (true) or point by point (the linear baseline)
  bool coherentCcd = true;               ///< tree: start each pair and role's query from its last front (same contacts)
  OctreeMode octree = OctreeMode::Full;  ///< cell skipping in grid fields
  int maxManifoldPoints = 4;             ///< manifold points reported per pair (0..4)
  /// Bullet convex shapes (box, sphere, capsule) against our field: the spacing of the points sampled on
  /// their surface, in cells of the field they meet, and at most 1/16 of the shape's thinnest size (beyond
  /// the paper; see registerWith()).
  double convexPointSpacingCells = 1.0;
  int convexMaxPoints = 20000;  ///< cap on the points sampled on one convex shape
  /// Benchmarks: every n-th step (n > 0) each query is repeated point by point (useTree = false), result
  /// discarded, and timed into SdfccdContactStatistics::shadowLinearSeconds (paper Table 4: linear vs tree
  /// on the very same motion). 0: off.
  int shadowLinearEvery = 0;
  /// Narrowphase threads: the CCD of the step's pairs of our shapes (and of ours against ground
  /// planes), both roles, runs on a persistent pool of this many threads (sdfccd_parallel_step.cpp); 0: the
  /// machine's hardware threads; 1: on the stepping thread. Results are bit-identical for every value. The pool's
  /// threads (this many minus the stepping thread) start at the first step with queries and stay parked between
  /// steps until the system goes.
  int threads = 0;
};

/// One body's penalty parameters (penalty mode), overriding the world's SdfccdContactSettings::penalty; an unset
/// field keeps the world's value. A pair combines its two bodies' values (a body without an override brings the
/// world's): stiffnesses like two springs in series, normalised so that equal values give that value
/// (2 a b / (a + b)); damping ratios and per-point damping by their mean. A pair where neither body has an
/// override uses the world's settings unchanged. The shell's density is the model's (BodyModelSettings::points).
/// An override must be of the world's law (setBodyContact refuses the others with one line): `stiffnessPerArea`
/// in a per-area world (the default), `stiffness` in a per-point one; `dampingRatio` where the world has an
/// explicit ratio, `damping` where it has per-point damping; where the world derives the ratio from restitution
/// (the default), a body's damping is its btRigidBody's restitution, combined the Bullet way.
struct SdfccdBodyContact {
  std::optional<double> stiffness;         ///< N/m per point (PenaltySettings::stiffness), >= 0
  std::optional<double> stiffnessPerArea;  ///< N/m^3 (PenaltySettings::stiffnessPerArea; 0: per-point law), >= 0
  std::optional<double> damping;           ///< N s/m per point (PenaltySettings::damping), >= 0
  std::optional<double> dampingRatio;      ///< zeta in [0, 2] (PenaltySettings::dampingRatio)
};

/// One (shell body, field body) role of a pair over the last step: the contact report.
struct SdfccdPairContact {
  const btCollisionObject* shellObject = nullptr;
  const btCollisionObject* fieldObject = nullptr;
  int contactCount = 0;               ///< shell points that produced a force
  double maxPenetration = 0.0;        ///< model units
  double maxPenetrationCells = 0.0;   ///< in cells of the field (a plane: of the shell body's field)
  Vec3 forceOnShell = Vec3::Zero();   ///< eq. (5) average over the step (N), world
  Vec3 torqueOnShell = Vec3::Zero();  ///< N m, about the shell body's centre of mass
  Vec3 forceOnField = Vec3::Zero();   ///< N
  Vec3 torqueOnField = Vec3::Zero();  ///< N m
  bool clamped = false;               ///< the pair triggered time-of-impact clamping
  double firstFraction = 1.0;         ///< earliest first hit of the step (fraction)
};

/// Counters, cumulative since construction.
struct SdfccdContactStatistics {
  /// Time of the rigid CCD queries (s), all fields, summed over the threads that ran them: steady-clock time
  /// (a thread CPU clock read is a system call, dearer than most queries a pile's certificates answer), or thread
  /// CPU time while shadowLinearEvery > 0 times the point-by-point repeat beside it (paper Table 4). A query the CCD
  /// history answers with no traversal is not timed.
  double ccdSeconds = 0.0;
  double groundCcdSeconds = 0.0;      ///< the part of ccdSeconds spent against static planes (s)
  double shadowLinearSeconds = 0.0;   ///< point-by-point repeats (shadowLinearEvery), between bodies only (s)
  std::int64_t shadowSteps = 0;       ///< steps in which the repeats ran
  double penaltySeconds = 0.0;        ///< wall time integrating the penalty model (s)
  std::int64_t ccdQueries = 0;        ///< rigid CCD queries (two per body pair and step)
  std::int64_t segmentQueries = 0;    ///< segment queries inside them
  std::int64_t clamps = 0;            ///< bodies moved back to a time of impact
  std::int64_t kinematicPushes = 0;   ///< clamps against a kinematic body (no rewind; time_of_impact_clamp.h)
  std::int64_t softenedPairs = 0;     ///< roles whose stiffness the omega dt cap softened (contact_material.h)
  std::int64_t unsupportedPairs = 0;  ///< processPair calls for pairs we do not handle (no contact)
  /// processPair calls skipped because a body's pose, velocity or motion was NaN or infinite: such a body
  /// gets no contact, so nothing non-finite reaches the other body (SceneWorld rejects it before the step).
  std::int64_t nonFinitePairs = 0;
  double maxPenetrationCells = 0.0;  ///< largest penetration seen (cells)
  // Work counters: what each effect cost (zero when a scene does not ask for the effect).
  std::int64_t groundCcdQueries = 0;     ///< rigid CCD queries against static planes (the "ground" effect)
  std::int64_t penaltySamples = 0;       ///< penalty force samples in contact (PenaltyResult::samples)
  std::int64_t dampingEvaluations = 0;   ///< of them, with the damping term ("damping")
  std::int64_t torqueEvaluations = 0;    ///< of them, with torques ("rotation")
  std::int64_t frictionEvaluations = 0;  ///< of them, with friction ("friction")
  /// Pairs that ran no CCD because neither body moves: each sleeping, static, or kinematic at zero velocity
  /// (their manifolds keep last step's points for Bullet's island manager).
  std::int64_t restingPairs = 0;
  std::int64_t deferredQueries = 0;  ///< of ccdQueries, those computed in a step's parallel batch
  double parallelWallSeconds = 0.0;  ///< wall time of the parallel batches (s)
};

class SdfccdContactSystem : public btActionInterface {
 public:
  explicit SdfccdContactSystem(const SdfccdContactSettings& settings = {});
  ~SdfccdContactSystem() override;
  SdfccdContactSystem(const SdfccdContactSystem&) = delete;
  SdfccdContactSystem& operator=(const SdfccdContactSystem&) = delete;

  const SdfccdContactSettings& settings() const { return m_settings; }
  /// Takes effect at the next step. Throws sdfccd::Error on bad values.
  void setSettings(const SdfccdContactSettings& settings);

  /// Overwrites every dispatcher entry involving CUSTOM_CONCAVE_SHAPE_TYPE (see sdfccd_shape.h). Our
  /// algorithm for (ours, X) and (X, ours), contacts and closest points, for every X but compounds (Bullet's
  /// compound algorithms stay, and dispatch each child pair back to ours) and btEmptyShape. A convex X takes
  /// both roles like ours: its surface points (sampled once per size, convexPointSpacingCells) against our
  /// field, and our shell against its exact field (BoxField, SphereField, CapsuleField; RevolvedConvexField for
  /// cylinders and cones; the ConvexPolytopeField of its hull for any other convex shape). Triangle meshes and
  /// terrain: our shell against the triangles near our body, their vertices against our field. Any other X
  /// (bullet_shape_fields.h) is announced once (setLogCallback) and counted in unsupportedPairs. The
  /// create functions are owned by this object: keep it alive as long as the dispatcher (registerSdfccdAlgorithms()
  /// does this for you).
  void registerWith(btCollisionDispatcher& dispatcher);

  /// The world whose overlapping pairs a step plans and computes in parallel (sdfccd_parallel_step.cpp);
  /// registerSdfccdAlgorithms(world) attaches it. Without a world every pair is computed when Bullet processes
  /// it, on the stepping thread. Null detaches.
  void attachWorld(btCollisionWorld* world) { m_world = world; }

  /// Per-body penalty parameters (see SdfccdBodyContact), taking effect at the next step. The body is a key only
  /// (not owned, never dereferenced): clear its entry when the body is destroyed, or a new body at its address
  /// inherits it. Throws sdfccd::Error on a null body or bad values.
  void setBodyContact(const btCollisionObject* body, const SdfccdBodyContact& contact);
  void clearBodyContact(const btCollisionObject* body);
  /// The body's override, or null.
  const SdfccdBodyContact* bodyContact(const btCollisionObject* body) const;

  /// btActionInterface: clamping and impulses after integrateTransforms (see the file comment).
  void updateAction(btCollisionWorld* world, btScalar timeStep) override;
  void debugDraw(btIDebugDraw*) override {}

  /// The roles that had contact in the last completed step.
  const std::vector<SdfccdPairContact>& lastStepContacts() const { return m_lastContacts; }
  /// Total contact points and largest penetration (cells) of the last completed step.
  int lastStepContactCount() const { return m_lastContactCount; }
  double lastStepMaxPenetrationCells() const { return m_lastMaxPenetrationCells; }
  int lastStepClamps() const { return m_lastClamps; }
  const SdfccdContactStatistics& statistics() const { return m_stats; }
  /// Where the one-line announcements go (an unsupported pair of shape types, once per type pair and system);
  /// stderr by default; an empty callback silences them. The pairs are counted in
  /// SdfccdContactStatistics::unsupportedPairs either way.
  void setLogCallback(SdfccdLogCallback callback) { m_log = std::move(callback); }

  /// Called by SdfccdCollisionAlgorithm. `closestPointsOnly`: a contactTest query: report the points inside
  /// at the current poses, change nothing.
  /// `solverPair`: the algorithm's solver-mode state (its extra manifolds; made with createSolverPair, owned by the
  /// algorithm, destroyed with destroySolverPair); null in penalty mode.
  void processPair(const btCollisionObjectWrapper* wrap0, const btCollisionObjectWrapper* wrap1,
                   const btDispatcherInfo& dispatchInfo, btManifoldResult* resultOut, btPersistentManifold* manifold,
                   SdfccdSolverPair* solverPair, bool closestPointsOnly);
  /// A new solver pair for an algorithm whose own manifold is `primary`.
  static SdfccdSolverPair* createSolverPair(btDispatcher* dispatcher, const btPersistentManifold* primary);
  /// Releases a solver pair's extra manifolds (through `dispatcher`) and deletes it. Null is allowed.
  static void destroySolverPair(SdfccdSolverPair* solverPair, btDispatcher* dispatcher);
  /// Appends the solver pair's manifolds (the extra ones; the algorithm adds its own).
  static void solverPairManifolds(const SdfccdSolverPair* solverPair, btManifoldArray& manifoldArray);

 private:
  struct BodyStep;
  using Record = detail::ContactRecord;  // one role's step (contact_step.h)
  struct Role;
  /// A body's contact load of one step (per-area law): the stiffness and damping its contacts put on it.
  struct ContactLoad {
    double stiffness = 0.0;  ///< N/m, over its pairs; a pair of two dynamic bodies counts twice (Gershgorin)
    double damping = 0.0;    ///< N s/m, over its pairs
  };
  struct AnchorSlot;
  /// This step's motion of the wrapper's object (once per step); `contactMass`: apply applyContactMass.
  BodyStep& bodyStep(const btCollisionObjectWrapper* wrap, double timeStep, bool contactMass);
  /// The friction anchors and CCD history of (manifold, role), created on first use and kept across steps.
  AnchorSlot& anchorSlot(const btPersistentManifold* manifold, int role, const btCollisionObject* shell,
                         const btCollisionObject* field);
  void applyPenaltyImpulses(const Record& record);
  /// Per-area law: scales a dynamic body's mass for the contact response by last step's contact load.
  void applyContactMass(BodyStep& step, double timeStep) const;
  /// Per-area law: adds this role's stiffness and damping (`coefficients`) to its bodies' next load.
  void addContactLoad(const Record& record, double roleScale, const PairResponseCoefficients& coefficients);
  static ImpactBody impactBody(const BodyStep& body);
  /// The world's penalty settings with the two bodies' overrides (setBodyContact) combined.
  PenaltySettings combinedPenalty(const btCollisionObject* a, const btCollisionObject* b) const;
  static void setVelocities(const BodyStep& body, const ImpactBody& impact);
  /// The surface points of a supported convex shape at the spacing for a field of `fieldCellSize` (cached).
  const PointTree& convexShellTree(const btCollisionShape* shape, double fieldCellSize);
  /// The shell of a shape that is not ours (box, sphere, capsule or any other convex shape; cached), spaced for
  /// a field of `fieldCellSize`; null for a degenerate convex shape (other_shape_roles.cpp).
  const PointTree* otherShellTree(const btCollisionShape* shape, double fieldCellSize);
  /// Counts an unsupported pair and announces its shape types once (other_shape_roles.cpp).
  void reportUnsupported(const btCollisionShape* shape0, const btCollisionShape* shape1);
  /// A triangle mesh's role as field: its triangles within `pad` of the box the shell sweeps over the step
  /// (relative to the mesh), in the mesh's frame; nothing when there are none (other_shape_roles.cpp).
  std::optional<TriangleSetField> meshFieldNear(const Role& role, const btCollisionShape* shellShape,
                                                const btCollisionShape* meshShape, double pad) const;
  /// A triangle mesh's role as shell: its vertices in the box our body (the role's field) sweeps, each with the
  /// normal of its triangles turned towards our body; null when there are none (other_shape_roles.cpp).
  const PointTree* meshVertexTree(const Role& role, const btCollisionShape* meshShape,
                                  const btCollisionShape* ourShape);
  template <class Field>
  void processRole(const Role& role, const Field& field, double thresholdCells, double cellSize, double timeStep,
                   btManifoldResult* resultOut, bool closestPointsOnly);
  /// Penalty mode, planning: queues the role's work (penalty_role.h) in the step's batch.
  template <class Field>
  void queuePenaltyRole(const Role& role, const Field& field, const detail::PenaltyRoleFacts<BodyStep>& facts);
  /// `frame` at an address that lasts through the step: `kept` when given, a shared identity, or a copy in the
  /// batch's slots.
  const Rigid* lastingFrame(const Rigid& frame, const Rigid* kept);
  /// Penalty mode, after a role's work (penalty_role.h, on the pool or here): statistics, manifold points, the
  /// record, the impulses (serial: it touches Bullet).
  void applyPenaltyRole(const detail::RoleResult& result, btManifoldResult* resultOut, bool closestPointsOnly);
  /// Solver mode, after a role's work: statistics, the pair's candidates, the record.
  void applySolverRole(const detail::RoleResult& result);
  /// A pair whose roles the step's plan computed: applies them in role order, then (solver mode, `solverPair`
  /// not null) writes its manifolds (sdfccd_parallel_step.cpp).
  void applyPlannedPair(const btCollisionObjectWrapper* wrap0, const btCollisionObjectWrapper* wrap1,
                        const btDispatcherInfo& dispatchInfo, btManifoldResult* resultOut,
                        btPersistentManifold* manifold, SdfccdSolverPair* solverPair);
  /// Solver mode, one role: the CCD with the speculative margin, each listed point as a candidate at the step's
  /// start (appended to m_candidates; normals on the manifold's body 1). `shellIsManifoldBody0`: the shell
  /// belongs to the manifold's body 0.
  template <class Field>
  void collectSolverCandidates(const Role& role, const Field& field, double cellSize, bool shellIsManifoldBody0);
  /// The step's plan (sdfccd_parallel_step.cpp): the first processPair of a step runs every overlapping pair of
  /// ours in planning mode (queries queued, nothing else changed), then computes the queue on the pool.
  void planStep(const btDispatcherInfo& dispatchInfo);
  /// The role's result from this step's parallel batch, or null (not planned, or in planning mode).
  const detail::RoleResult* takePlanned(const Role& role, bool deferrableField);
  /// One role's work, run(input, result): planning mode queues it (when the role may be deferred) and returns
  /// null (the caller stops); otherwise runs it now into m_roleScratch and returns that (parallel_step.h).
  template <class Input, class Run>
  const detail::RoleResult* runOrQueue(const Role& role, bool deferrableField, const Input& input, Run run);
  /// Solver mode, the whole pair: reduction and the manifold points (solver_manifolds.cpp).
  void writeSolverManifolds(const btCollisionObjectWrapper* wrapA, const btCollisionObjectWrapper* wrapB,
                            btPersistentManifold* primary, SdfccdSolverPair& pair);

  SdfccdContactSettings m_settings;
  std::vector<std::unique_ptr<btCollisionAlgorithmCreateFunc>> m_createFuncs;
  std::unordered_map<std::string, std::unique_ptr<PointTree>> m_convexTrees;       // by shape type, sizes, spacing
  std::unordered_map<const btCollisionObject*, SdfccdBodyContact> m_bodyContacts;  // setBodyContact
  std::unique_ptr<detail::ConvexShapeCache> m_convexShapes;  // other convex shapes' fields and shells
  std::unique_ptr<PointTree> m_meshVertices;                 // the current mesh role's vertices (one role at a time)
  SdfccdLogCallback m_log;                                   // announcements (stderr unless set)
  std::set<std::pair<int, int>> m_announcedPairs;            // shape type pairs announced unsupported
  std::vector<BodyStep> m_bodies;
  std::unordered_map<const btCollisionObject*, std::size_t> m_bodyIndex;
  // A guess per world array index (btCollisionObject::getWorldArrayIndex) of the object's place in m_bodies, tried
  // before the map (bodyStep): right when that place holds the object, never reset.
  std::vector<std::size_t> m_bodyGuess;
  std::vector<Record> m_records;
  // Per-area law: each dynamic body's contact load of the last step (read) and of this step (written).
  std::unordered_map<const btCollisionObject*, ContactLoad> m_contactLoads, m_nextContactLoads;
  using SlotKey = std::pair<const btPersistentManifold*, int>;
  struct SlotKeyHash {
    std::size_t operator()(const SlotKey& k) const {
      return std::hash<const void*>()(k.first) ^ (static_cast<std::size_t>(k.second) * 0x9e3779b97f4a7c15ull);
    }
  };
  // The slots (an 80-body pile has ~2,000), and the order in which this and the last step's walk met them.
  std::unordered_map<SlotKey, std::unique_ptr<AnchorSlot>, SlotKeyHash> m_anchorSlots;
  struct SlotVisit {  // one slot met in a step's walk (anchorSlot): its key, slot, objects and step
    SlotKey key;
    AnchorSlot* slot;
    const btCollisionObject* shellObject;
    const btCollisionObject* fieldObject;
    std::int64_t step;
  };
  std::vector<SlotVisit> m_slotOrder, m_lastSlotOrder;
  std::size_t m_slotCursor = 0;
  std::vector<SdfccdPairContact> m_lastContacts;
  ContactQueryResult m_scratch;                // reused by every role: keeps the CCD's buffers
  std::vector<ContactCandidate> m_candidates;  // solver mode: the current pair's candidates (both roles)
  std::vector<double> m_candidateBounce;  // solver mode: per candidate, added to its restitution (solver_contacts.cpp)
  std::vector<double> m_candidateDistance;  // solver mode: per candidate, the distance Bullet's solver gets (m)
  double m_candidateMargin = 0.0;           // solver mode: the current pair's largest speculative margin (m)
  double m_solverTimeStep = 0.0;            // solver mode: the step of the current pair (s)
  // The parallel step (sdfccd_parallel_step.cpp): the planned queries, the pool, the world whose pairs are planned.
  std::unique_ptr<detail::DeferredQueries> m_deferred;
  std::unique_ptr<detail::NarrowphasePool> m_pool;
  btCollisionWorld* m_world = nullptr;
  bool m_planning = false;                    // processPair runs to queue queries only
  std::vector<int> m_plannedPairs;            // the step's planned pairs (indices into the overlapping pair array)
  std::vector<const void*> m_planIncomplete;  // manifolds with a role the batch refused (runOrQueue; none expected)
  std::int64_t m_plannedStep = -1;            // the m_stepCounter of the last plan
  std::unique_ptr<detail::RoleResult> m_roleScratch;  // a role computed on the stepping thread (keeps buffers)
  std::int64_t m_stepCounter = 0;
  int m_lastContactCount = 0;
  double m_lastMaxPenetrationCells = 0.0;
  int m_lastClamps = 0;
  SdfccdContactStatistics m_stats;
};

/// Registration, the one call a Bullet program makes (after creating the world, before stepping it):
/// @code
///   sdfccd::registerSdfccdAlgorithms(&world);   // or keep the returned pointer to read contacts and statistics
/// @endcode
/// Ownership and lifetime: the dispatcher's registration owns the system (a process-wide table keyed by the
/// dispatcher holds a std::shared_ptr), so the returned pointer may be dropped: the system lives until the same
/// dispatcher is registered again or releaseSdfccdAlgorithms() is called. A program that creates many worlds
/// calls releaseSdfccdAlgorithms(&world) before destroying each (else each keeps its system's memory until its
/// dispatcher's address is registered again). Registering a dispatcher again through the dispatcher overload while
/// its registration is live is refused (sdfccd::Error); the world overload replaces it (its pair algorithms go).
///
/// Threads: the narrowphase must run on one thread. A btDiscreteDynamicsWorldMt or a btCollisionDispatcherMt is
/// refused (sdfccd::Error); use btDiscreteDynamicsWorld with btCollisionDispatcher.
///
/// Creates a contact system, registers its algorithms with `dispatcher` (every pair involving our shape type,
/// both orders, contacts and closest points) and returns it. Add it to the dynamics world with
/// `world.addAction(system.get())` — or use the overload below, which does both. Throws sdfccd::Error on a null
/// or multi-threaded dispatcher and on bad settings. In solver mode (the default) build the world with the
/// constraint solver of sdfccd/bullet/contact_solver.h (makeContactSolver, configureContactSolver): Bullet's default
/// sequential-impulse solver lets stacks and heavy-on-light pairs creep.
std::shared_ptr<SdfccdContactSystem> registerSdfccdAlgorithms(btCollisionDispatcher* dispatcher,
                                                              const SdfccdContactSettings& settings = {});
/// Registers with the world's dispatcher (must be a btCollisionDispatcher, not the Mt one) and adds the system as
/// an action. Throws sdfccd::Error on a null or multi-threaded world.
std::shared_ptr<SdfccdContactSystem> registerSdfccdAlgorithms(btDiscreteDynamicsWorld* world,
                                                              const SdfccdContactSettings& settings = {});
/// Undoes registerSdfccdAlgorithms(world): removes the action, frees the algorithms of the world's current pairs
/// that are ours, points every dispatcher entry of our shape type at btEmptyAlgorithm (no contact) and lets the
/// system go (it is deleted once no returned pointer holds it). The world stays usable. Does nothing when the
/// world's dispatcher has no registration. Call it before destroying the world, not after.
void releaseSdfccdAlgorithms(btDiscreteDynamicsWorld* world);

}  // namespace sdfccd
