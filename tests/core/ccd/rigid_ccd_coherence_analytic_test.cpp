/// @file
/// @brief The coherent every-contact query (rigid_ccd_coherence.h) against the analytic plane and box, whose
/// histories are keyed by the fields' values: random walks over tilted planes and around a box, far from the
/// origin too, grazing the ground, zero-length motion, and a plane with other values under the same history.
/// Every step runs the whole-front fast path first (when it answers, the fresh query must find nothing), else
/// the coherent query, which must return the fresh query's contacts bit for bit. Each test also checks that the
/// history did skip work and that contacts occurred (so it can fail both ways).
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "core/ccd/rigid_ccd_test_util.h"
#include "sdfccd/ccd/rigid_ccd.h"
#include "sdfccd/ccd/rigid_ccd_coherence.h"
#include "sdfccd/field/analytic_fields.h"

namespace sdfccd {
namespace analytic_coherence_test {

struct Counts {
  int clear = 0;               // steps the whole-front fast path answered
  std::int64_t certified = 0;  // front nodes the coherent queries certified
  int contacts = 0;            // contacts the fresh query found
};

/// One step both ways: the fast path (then the fresh query must be empty), else the coherent query (then its
/// contacts must be the fresh one's bit for bit).
template <class Field>
void step(const PointTree& tree, const Field& field, const Rigid& a, const Rigid& b, const RigidCcdSettings& s,
          RigidCcdCoherence& history, const std::string& what, Counts& counts) {
  RigidCcdResult fresh;
  rigidCcd(tree, field, a, b, s, fresh);
  counts.contacts += static_cast<int>(fresh.contacts.size());
  RigidCcdResult coherent;
  coherent.contacts.emplace_back();  // must be cleared by either path
  if (rigidCcdCertifiedClear(tree, field, a, b, s, history, coherent)) {
    ++counts.clear;
    EXPECT_TRUE(fresh.contacts.empty()) << what << ": certified clear, but the fresh query touches";
    EXPECT_TRUE(coherent.contacts.empty()) << what;
    return;
  }
  rigidCcd(tree, field, a, b, s, history, coherent);
  counts.certified += coherent.stats.certified;
  test::expectSameContacts(fresh, coherent, what);
}

/// A random step from `pose`: a rotation of about `size` rad and a translation of about `size` units.
Rigid randomStep(const Rigid& pose, double size, std::mt19937& rng) {
  std::normal_distribution<double> noise(0.0, 1.0);
  Rigid next = pose;
  next.translation() += size * Vec3(noise(rng), noise(rng), noise(rng));
  next.linear() = pose.linear() * Eigen::AngleAxisd(size * noise(rng), Vec3::UnitZ()).toRotationMatrix() *
                  Eigen::AngleAxisd(size * noise(rng), Vec3::UnitX()).toRotationMatrix();
  return next;
}

/// A walk of `steps` random steps (small ones, a large one now and then, a still one now and then: the
/// discrete model's zero-length query) that stays within `leash` of `home`, where it restarts.
template <class Field>
void randomWalk(const PointTree& tree, const Field& field, const Rigid& home, double leash, int steps,
                const RigidCcdSettings& s, std::mt19937& rng, const std::string& what, Counts& counts) {
  RigidCcdCoherence history;
  Rigid pose = home;
  for (int k = 0; k < steps; ++k) {
    const double size = k % 23 == 0 ? 0.2 : 0.004;
    Rigid next = k % 7 == 3 ? pose : randomStep(pose, size, rng);
    if ((next.translation() - home.translation()).norm() > leash) next = home;
    step(tree, field, pose, next, s, history, what + " step " + std::to_string(k), counts);
    pose = next;
  }
}

TEST(RigidCcdCoherenceAnalytic, RandomWalksOverPlanesEqualFreshNearAndFarFromTheOrigin) {
  std::mt19937 rng(41);
  std::normal_distribution<double> noise(0.0, 1.0);
  const PointTree tree(test::randomShell(500, 0.5, rng));
  Counts counts;
  // Far from the origin the coordinates are 1e3 and 1e5 times the shell: the points' positions and the plane's
  // value round relative to them, which the certificates' slack must cover.
  const double distances[] = {0.0, 1e3, 1e5};
  for (int config = 0; config < 6; ++config) {
    const Vec3 normal = config == 0 ? Vec3::UnitY() : Vec3(noise(rng), noise(rng), noise(rng)).normalized();
    const Vec3 origin = distances[config % 3] * Vec3(noise(rng), noise(rng), noise(rng)).normalized();
    const PlaneField plane(normal, normal.dot(origin));
    const RigidCcdSettings s = test::variedSphereSettings(config);
    // Home: the shell's centre 0.5 above the plane, so that its lower points dip in and out along the walk.
    Rigid home = Rigid::Identity();
    home.translation() = origin + (0.5 + s.sigma) * plane.normal();
    randomWalk(tree, plane, home, 0.15, 300, s, rng, "plane " + std::to_string(config), counts);
  }
  EXPECT_GT(counts.contacts, 300);
  EXPECT_GT(counts.clear, 100);
  EXPECT_GT(counts.certified, 1000);
}

TEST(RigidCcdCoherenceAnalytic, RandomWalksAroundABoxEqualFresh) {
  std::mt19937 rng(43);
  std::normal_distribution<double> noise(0.0, 1.0);
  const PointTree tree(test::randomShell(500, 0.3, rng));
  const BoxField box(Vec3(0.5, 0.3, 0.8));
  Counts counts;
  for (int config = 0; config < 6; ++config) {
    const RigidCcdSettings s = test::variedSphereSettings(config);
    // Home: near a face, an edge or a corner of the box (the field's formula changes there).
    const Vec3 direction = Vec3(noise(rng), noise(rng), noise(rng)).normalized();
    Rigid home = Rigid::Identity();
    home.translation() = box.halfExtents().cwiseProduct(direction) + (0.33 + s.sigma) * direction;
    randomWalk(tree, box, home, 0.1, 250, s, rng, "box " + std::to_string(config), counts);
  }
  EXPECT_GT(counts.contacts, 1000);
  EXPECT_GT(counts.clear, 50);
  EXPECT_GT(counts.certified, 1000);
}

TEST(RigidCcdCoherenceAnalytic, GrazingTheGroundFarAlongItEqualsFresh) {
  // A flat grid of points exactly at sigma above the ground (touching counts as contact), still, sliding and
  // lifted by tiny amounts, near the origin and 1e5 away along the ground.
  PointShell shell;
  for (int i = 0; i < 16; ++i) {
    for (int j = 0; j < 16; ++j) {
      shell.positions.emplace_back(0.01 * i, 0.0, 0.01 * j);
      shell.normals.emplace_back(0.0, -1.0, 0.0);
      shell.areas.push_back(1e-4);
    }
  }
  const PointTree tree(shell);
  const PlaneField ground = PlaneField::ground();
  RigidCcdSettings s;
  s.sigma = 0.001;
  Counts counts;
  const double lifts[] = {1e-3, 1e-3, 0.0, 0.0, 1e-16, 1e-12, 1e-9, 1e-9, 0.0, -1e-12, 1e-6, 1e-6, 0.0, 1e-3, 1e-3};
  for (const double along : {0.0, 1e5}) {
    RigidCcdCoherence history;
    for (int k = 0; k < 15; ++k) {
      Rigid a = Rigid::Identity();
      a.translation() = Vec3(along + 0.001 * k, s.sigma + lifts[k], 0.0);
      Rigid b = a;
      if (k % 3 != 1) b.translation().x() += 0.001;  // every third step is still
      step(tree, ground, a, b, s, history, "grazing at " + std::to_string(along) + " step " + std::to_string(k),
           counts);
    }
  }
  EXPECT_GT(counts.contacts, 0);
  EXPECT_GT(counts.clear + counts.certified, 0);
}

TEST(RigidCcdCoherenceAnalytic, APlaneWithOtherValuesStartsAfresh) {
  // The history is keyed by the plane's values: a plane raised into the shell, at the same address (Bullet
  // builds its ground per step), must not inherit the low plane's certificates; and the low plane again (a new
  // object with the same values) may reuse the history.
  std::mt19937 rng(47);
  const PointTree tree(test::randomShell(400, 0.5, rng));
  const RigidCcdSettings s;
  Rigid pose = Rigid::Identity();
  pose.translation() = Vec3(0.0, 1.0, 0.0);
  RigidCcdCoherence history;
  Counts low;
  Counts high;
  for (int k = 0; k < 12; ++k) {
    const double offset = k % 4 == 3 ? 0.8 : 0.0;  // the raised plane cuts the shell
    const PlaneField plane(Vec3::UnitY(), offset);
    step(tree, plane, pose, pose, s, history, "offset " + std::to_string(offset) + " step " + std::to_string(k),
         offset > 0.0 ? high : low);
  }
  EXPECT_EQ(low.contacts, 0);
  EXPECT_GT(low.clear, 0);  // the same values: the history holds
  EXPECT_GT(high.contacts, 0);
  EXPECT_EQ(high.clear, 0);
}

}  // namespace analytic_coherence_test
}  // namespace sdfccd
