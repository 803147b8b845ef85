// NaN and infinite input to the core queries (injected state is rejected, never propagated): a rigid CCD with a
// non-finite pose throws one-line sdfccd::Error and leaves no contacts behind; a segment query with a non-finite end
// point answers Failed (segment_ccd.h) for the grid and the analytic fields; the penalty model rejects a non-finite
// timestep. The same query with the NaN replaced by a finite value succeeds (the error is about the NaN, not about the
// setup).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include "sdfccd/ccd/rigid_ccd.h"
#include "sdfccd/error.h"
#include "sdfccd/field/analytic_fields.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/response/penalty_model.h"

namespace sdfccd {
namespace {

const double kNan = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();

// A small shell: the 8 corners of a cube of half size 0.1 with diagonal normals.
PointShell cubeCorners() {
  PointShell shell;
  for (int c = 0; c < 8; ++c) {
    const Vec3 corner((c & 1) ? 0.1 : -0.1, (c & 2) ? 0.1 : -0.1, (c & 4) ? 0.1 : -0.1);
    shell.positions.push_back(corner);
    shell.normals.push_back(corner.normalized());
  }
  return shell;
}

// phi = |p| - 0.5 sampled on a 17^3 grid over [-1, 1]^3.
std::shared_ptr<const SdfGrid> sphereGrid() {
  const int n = 17;
  const double h = 2.0 / (n - 1);
  std::vector<float> values;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) values.push_back(float(Vec3(-1 + i * h, -1 + j * h, -1 + k * h).norm() - 0.5));
  return std::make_shared<const SdfGrid>(Vec3i(n, n, n), Vec3(-1, -1, -1), h, std::move(values));
}

Rigid at(const Vec3& t) {
  Rigid r = Rigid::Identity();
  r.translation() = t;
  return r;
}

template <class Field>
void expectRigidCcdRejects(const Field& field) {
  const PointTree tree(cubeCorners());
  RigidCcdResult result;
  // Finite: the cube falls through the level set and hits.
  rigidCcd(tree, field, at(Vec3(0, 0.9, 0)), at(Vec3(0, 0.3, 0)), RigidCcdSettings{}, result);
  ASSERT_FALSE(result.contacts.empty());
  Rigid rotatedNan = Rigid::Identity();
  rotatedNan.linear()(1, 1) = kNan;
  const Rigid bad[] = {at(Vec3(kNan, 0.9, 0)), at(Vec3(0, kInf, 0)), at(Vec3(0, -kInf, 0)), rotatedNan};
  for (const Rigid& pose : bad) {
    for (int end = 0; end < 2; ++end) {
      const Rigid start = end ? at(Vec3(0, 0.9, 0)) : pose;
      const Rigid finish = end ? pose : at(Vec3(0, 0.3, 0));
      try {
        rigidCcd(tree, field, start, finish, RigidCcdSettings{}, result);
        ADD_FAILURE() << "a non-finite pose was accepted";
      } catch (const Error& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("non-finite"), std::string::npos) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
      }
      EXPECT_TRUE(result.contacts.empty());  // cleared, not the previous query's contacts
    }
  }
  RigidCcdSettings nanSigma;
  nanSigma.sigma = kNan;
  EXPECT_THROW(rigidCcd(tree, field, at(Vec3(0, 0.9, 0)), at(Vec3(0, 0.3, 0)), nanSigma, result), Error);
}

TEST(NonFiniteInput, RigidCcdRejectsNonFinitePosesOnGridAndAnalyticFields) {
  expectRigidCcdRejects(GridField(sphereGrid()));
  expectRigidCcdRejects(PlaneField(Vec3::UnitY(), 0.25));  // the plane y = 0.25
  expectRigidCcdRejects(SphereField(Vec3::Zero(), 0.5));
}

template <class Field>
void expectSegmentFails(const Field& field) {
  SegmentCcdSettings s;
  EXPECT_EQ(intersectSegment(field, Vec3(0, 0.9, 0), Vec3(0, 0.0, 0), s).state, SegmentState::Hit);
  for (const Vec3& bad : {Vec3(kNan, 0, 0), Vec3(0, kInf, 0), Vec3(0, 0, -kInf)}) {
    EXPECT_EQ(intersectSegment(field, bad, Vec3(0, 0.0, 0), s).state, SegmentState::Failed);
    EXPECT_EQ(intersectSegment(field, Vec3(0, 0.9, 0), bad, s).state, SegmentState::Failed);
  }
}

TEST(NonFiniteInput, SegmentQueriesFailOnNonFiniteEnds) {
  expectSegmentFails(GridField(sphereGrid()));
  expectSegmentFails(PlaneField(Vec3::UnitY(), 0.0));
  expectSegmentFails(SphereField(Vec3::Zero(), 0.5));
}

TEST(NonFiniteInput, PenaltyModelRejectsNonFiniteTimestepAndStiffness) {
  const PointTree tree(cubeCorners());
  const PlaneField plane(Vec3::UnitY(), 0.0);
  RigidCcdResult ccd;
  rigidCcd(tree, plane, at(Vec3(0, 0.05, 0)), at(Vec3(0, 0.05, 0)), RigidCcdSettings{}, ccd);
  ASSERT_FALSE(ccd.contacts.empty());
  const ShellMotion shell = ShellMotion::fixed(at(Vec3(0, 0.05, 0)));
  const FieldMotion ground = FieldMotion::fixed(Rigid::Identity());
  const PenaltySettings good;
  EXPECT_GT(integratePenalty(tree.shell().positions, plane, ccd, shell, ground, 0.001, good).contactCount, 0);
  for (const double dt : {kNan, kInf, 0.0, -0.001}) {
    EXPECT_THROW(integratePenalty(tree.shell().positions, plane, ccd, shell, ground, dt, good), Error) << dt;
  }
  PenaltySettings nanStiffness;
  nanStiffness.stiffness = kNan;
  EXPECT_THROW(integratePenalty(tree.shell().positions, plane, ccd, shell, ground, 0.001, nanStiffness), Error);
}

}  // namespace
}  // namespace sdfccd
