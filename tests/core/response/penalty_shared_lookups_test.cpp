/// @file
/// @brief integratePenaltyWithCoefficients (what queryContacts runs) against perAreaCoefficients followed by
/// integratePenalty: it shares the field lookups at the contacts' end positions between the two, and must give
/// the same coefficients, impulses, counters and anchors bit for bit, step after step, on a grid field (where
/// the sharing applies) and on the analytic plane.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "core/segment_reference.h"
#include "sdfccd/ccd/rigid_ccd.h"
#include "sdfccd/field/analytic_fields.h"
#include "sdfccd/field/grid_field.h"
#include "sdfccd/mesh/procedural_meshes.h"
#include "sdfccd/response/penalty_model.h"
#include "sdfccd/shell/point_shell.h"
#include "sdfccd/shell/point_tree.h"

namespace sdfccd::penalty_shared_lookups_test {
namespace {

void expectSameVec(const Vec3& a, const Vec3& b, const std::string& what) {
  for (int k = 0; k < 3; ++k) EXPECT_EQ(a[k], b[k]) << what << " [" << k << "]";
}

void expectSameResult(const PenaltyResult& a, const PenaltyResult& b, const std::string& what) {
  expectSameVec(a.impulseOnShell, b.impulseOnShell, what + " impulseOnShell");
  expectSameVec(a.angularImpulseOnShell, b.angularImpulseOnShell, what + " angularImpulseOnShell");
  expectSameVec(a.impulseOnField, b.impulseOnField, what + " impulseOnField");
  expectSameVec(a.angularImpulseOnField, b.angularImpulseOnField, what + " angularImpulseOnField");
  EXPECT_EQ(a.maxPenetration, b.maxPenetration) << what;
  EXPECT_EQ(a.contactCount, b.contactCount) << what;
  EXPECT_EQ(a.samples, b.samples) << what;
  EXPECT_EQ(a.frictionEvaluations, b.frictionEvaluations) << what;
  EXPECT_EQ(a.slippingPoints, b.slippingPoints) << what;
}

void expectSameAnchors(const FrictionAnchorTable& a, const FrictionAnchorTable& b, const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a.anchors()[i].point, b.anchors()[i].point) << what;
    expectSameVec(a.anchors()[i].anchorInField, b.anchors()[i].anchorInField, what + " anchor");
  }
}

/// What the two ways saw over a run (so that a run which never reached the shared code cannot pass).
struct RunCounts {
  std::int64_t samples = 0;
  int slipping = 0;
  int anchoredSteps = 0;
};

/// A sphere shell (its point areas from the sampler) sliding and turning through `field` for `steps` steps of
/// 1 ms while the field body turns too, pressed `depth` (model units) in: each step's CCD, then both ways, each
/// with its own anchor table, compared bit for bit.
template <class Field>
RunCounts compareWays(const Field& field, const Vec3& startCentre, const Vec3& stepMove, PenaltyDirection direction,
                      double cellSize, int steps) {
  ShellSamplingSettings sampling;
  sampling.points = 300;
  sampling.iterations = 5;
  const PointTree tree(sampleShell(makeIcosphere(0.3, 3), sampling), PointTreeSettings{});
  const std::vector<Vec3>& points = tree.shell().positions;
  PenaltySettings settings = PenaltySettings::trustworthy();
  settings.direction = direction;
  settings.roleScale = 0.5;
  settings.sigma = 0.0;
  FrictionAnchorTable separateAnchors;
  FrictionAnchorTable sharedAnchors;
  RunCounts counts;
  const double dt = 0.001;
  for (int step = 0; step < steps; ++step) {
    ShellMotion shell;
    shell.worldFromShellStart = Rigid::Identity();
    shell.worldFromShellStart.linear() = Eigen::AngleAxisd(0.03 * step, Vec3(0.2, 1.0, 0.3).normalized()).matrix();
    shell.worldFromShellStart.translation() = startCentre + step * stepMove;
    shell.worldFromShellEnd = Rigid::Identity();
    shell.worldFromShellEnd.linear() = Eigen::AngleAxisd(0.03 * (step + 1), Vec3(0.2, 1.0, 0.3).normalized()).matrix();
    shell.worldFromShellEnd.translation() = startCentre + (step + 1) * stepMove;
    shell.velocity.linearStart = shell.velocity.linearEnd = stepMove / dt;
    shell.velocity.angularStart = shell.velocity.angularEnd = 30.0 * Vec3(0.2, 1.0, 0.3).normalized();
    shell.mass.inverseMass = 1.0;
    shell.mass.inverseInertiaInWorld = 50.0 * Mat3::Identity();
    FieldMotion fieldBody;
    fieldBody.worldFromSdfStart.linear() = Eigen::AngleAxisd(0.001 * step, Vec3::UnitZ()).matrix();
    fieldBody.worldFromSdfEnd.linear() = Eigen::AngleAxisd(0.001 * (step + 1), Vec3::UnitZ()).matrix();
    fieldBody.velocity.angularStart = fieldBody.velocity.angularEnd = Vec3(0, 0, 1.0);
    fieldBody.mass.inverseMass = 0.5;
    fieldBody.mass.inverseInertiaInWorld = 10.0 * Mat3::Identity();

    RigidCcdSettings ccdSettings;
    ccdSettings.mode = CcdMode::AllIntervals;
    RigidCcdResult ccd;
    rigidCcd(tree, field, fieldBody.worldFromSdfStart.inverse() * shell.worldFromShellStart,
             fieldBody.worldFromSdfEnd.inverse() * shell.worldFromShellEnd, ccdSettings, ccd);
    const std::string what = "step " + std::to_string(step);

    PenaltyRoleInput separate;
    separate.areas = &tree.shell().areas;
    separate.cellSize = cellSize;
    separate.anchors = &separateAnchors;
    const PairResponseCoefficients separateCoefficients =
        perAreaCoefficients(points, field, ccd, shell, fieldBody, dt, settings, separate);
    const PenaltyResult separateResult = integratePenalty(points, field, ccd, shell, fieldBody, dt, settings, separate);

    PenaltyRoleInput shared;
    shared.areas = &tree.shell().areas;
    shared.cellSize = cellSize;
    shared.anchors = &sharedAnchors;
    PairResponseCoefficients sharedCoefficients;
    const PenaltyResult sharedResult = integratePenaltyWithCoefficients(points, field, ccd, shell, fieldBody, dt,
                                                                        settings, shared, sharedCoefficients);

    EXPECT_EQ(separate.stiffnessPerArea, shared.stiffnessPerArea) << what;
    EXPECT_EQ(separate.dampingPerStiffness, shared.dampingPerStiffness) << what;
    EXPECT_EQ(separateCoefficients.stiffnessScale, sharedCoefficients.stiffnessScale) << what;
    EXPECT_EQ(separateCoefficients.stiffnessCapped, sharedCoefficients.stiffnessCapped) << what;
    expectSameResult(separateResult, sharedResult, what);
    expectSameAnchors(separateAnchors, sharedAnchors, what);
    counts.samples += sharedResult.samples;
    counts.slipping += sharedResult.slippingPoints;
    if (sharedAnchors.size() > 0) ++counts.anchoredSteps;
  }
  return counts;
}

/// A ball of radius 0.8 sampled on a grid of 0.05 (a 48^3 box around it).
GridField ballGrid() {
  return GridField(
      test::sampleGrid(Vec3i(49, 49, 49), Vec3::Constant(-1.2), 0.05, [](const Vec3& p) { return p.norm() - 0.8; }));
}

TEST(PenaltySharedLookups, GridFieldGivesTheSeparateCallsResultsBitForBit) {
  const GridField field = ballGrid();
  // The shell's bottom starts 2 cm inside the ball's top and slides across it, sinking a little each step.
  for (PenaltyDirection direction :
       {PenaltyDirection::Blend, PenaltyDirection::FieldGradient, PenaltyDirection::ShellNormal}) {
    const RunCounts counts =
        compareWays(field, Vec3(0.0, 1.08, 0.0), Vec3(0.004, -0.0005, 0.001), direction, field.spacing(), 40);
    EXPECT_GT(counts.samples, 1000) << static_cast<int>(direction);
    EXPECT_EQ(counts.anchoredSteps, 40) << static_cast<int>(direction);
    EXPECT_GT(counts.slipping, 0) << static_cast<int>(direction);
  }
}

TEST(PenaltySharedLookups, PlaneGivesTheSeparateCallsResultsBitForBit) {
  const PlaneField ground = PlaneField::ground();
  const RunCounts counts =
      compareWays(ground, Vec3(0.0, 0.28, 0.0), Vec3(0.004, -0.0005, 0.001), PenaltyDirection::Blend, 0.01, 30);
  EXPECT_GT(counts.samples, 1000);
  EXPECT_EQ(counts.anchoredSteps, 30);
}

}  // namespace
}  // namespace sdfccd::penalty_shared_lookups_test
