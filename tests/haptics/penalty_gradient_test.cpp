/// @file
/// @brief The penalty renderer's contact gradient: d(contact wrench)/d(pose) against central finite differences of the
/// end-pose contact wrench summed by brute force over every shell point, for a tilted box pressed into a plane (its
/// edge and corner points have diagonal shell normals, so the force's direction differs from the field's normal), with
/// the force along the shell normal (paper) and along the field's gradient.
#include <gtest/gtest.h>

#include <cmath>

#include "haptics/haptic_test_scenes.h"
#include "sdfccd/haptics/haptic_scene.h"
#include "sdfccd/haptics/penalty_renderer.h"

namespace sdfccd::haptics {
namespace {

/// The contact wrench on the box at `worldFromBody` (about its centre, world): every point with phi < 0 pushes with
/// k |phi| along u (minus its world shell normal, or the plane's normal).
Vec6 bruteForceWrench(const PointTree& tree, const PlaneField& plane, const Rigid& worldFromBody, double k,
                      bool shellNormal) {
  Vec6 w = Vec6::Zero();
  const PointShell& shell = tree.shell();
  for (std::size_t i = 0; i < shell.positions.size(); ++i) {
    const Vec3 p = worldFromBody * shell.positions[i];
    const double d = plane.distance(p);
    if (!(d < 0.0)) continue;
    const Vec3 u = shellNormal ? Vec3(-(worldFromBody.linear() * shell.normals[i])) : plane.normal();
    const Vec3 f = -k * d * u;
    w.head<3>() += f;
    w.tail<3>() += (p - worldFromBody.translation()).cross(f);
  }
  return w;
}

void checkGradient(PenaltyDirection direction) {
  const HapticScene scene = loadHapticScene(test::scenePath("plane-slide.json"));
  ASSERT_TRUE(scene.plane.has_value());
  PenaltyRendererSettings s = scene.penalty;
  s.contact.model = PenaltyModel::Discrete;
  s.contact.direction = direction;
  s.contact.stiffness = 1000.0;
  s.timestep = 1e-3;
  // The box (half size 1 cm) tilted about a skew axis, its lowest corner 0.3 mm into the plane y = 0.
  Rigid start = Rigid::Identity();
  start.linear() = Eigen::AngleAxisd(0.2, Vec3(1, 0, 2).normalized()).toRotationMatrix();
  double lowest = 1e9;
  for (const Vec3& x : scene.tree->shell().positions) lowest = std::min(lowest, (start.linear() * x).y());
  start.translation() = Vec3(0.0, -lowest - 0.0003, 0.0);
  PenaltyRenderer renderer(ObstacleContacts(*scene.tree, *scene.plane, Rigid::Identity()), start, s);
  RigidBodyState device;
  device.worldFromBody = start;
  renderer.step(device);  // the gradient is evaluated at the pose this step ends at
  const Rigid at = renderer.state().worldFromBody;
  const bool shellNormal = direction == PenaltyDirection::ShellNormal;
  ASSERT_GT(bruteForceWrench(*scene.tree, *scene.plane, at, s.contact.stiffness, shellNormal).head<3>().norm(), 0.05);
  // Central differences, column by column; the error of a column relative to its size.
  const double eps[2] = {1e-7, 1e-6};  // m, rad
  Mat6 fd;
  for (int j = 0; j < 6; ++j) {
    Vec6 dx = Vec6::Zero();
    dx[j] = eps[j / 3];
    const double kp = s.contact.stiffness;
    fd.col(j) = (bruteForceWrench(*scene.tree, *scene.plane, displacePose(at, dx), kp, shellNormal) -
                 bruteForceWrench(*scene.tree, *scene.plane, displacePose(at, -dx), kp, shellNormal)) /
                (2.0 * dx[j]);
  }
  const auto worstColumnError = [&](const Mat6& k) {
    double worst = 0.0;
    for (int j = 0; j < 6; ++j) worst = std::max(worst, (k.col(j) - fd.col(j)).norm() / (fd.col(j).norm() + 1e-9));
    return worst;
  };
  EXPECT_LT(worstColumnError(renderer.contactGradient()), 1e-4) << renderer.contactGradient() << "\nFD:\n" << fd;
  // The symmetric approximation misses the torque's lever (and, with the shell normal, the force's direction).
  s.consistentGradient = false;
  PenaltyRenderer former(ObstacleContacts(*scene.tree, *scene.plane, Rigid::Identity()), start, s);
  former.step(device);
  EXPECT_GT(worstColumnError(former.contactGradient()), 1e-2);
}

TEST(PenaltyContactGradient, MatchesFiniteDifferencesWithTheShellNormal) {
  checkGradient(PenaltyDirection::ShellNormal);
}

TEST(PenaltyContactGradient, MatchesFiniteDifferencesWithTheFieldGradient) {
  checkGradient(PenaltyDirection::FieldGradient);
}

}  // namespace
}  // namespace sdfccd::haptics
