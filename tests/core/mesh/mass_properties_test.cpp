// Mass properties against closed forms: a translated, rotated box and a finely tessellated sphere.
#include "sdfccd/mesh/mass_properties.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "sdfccd/error.h"
#include "sdfccd/mesh/procedural_meshes.h"

namespace sdfccd {
namespace {

MassPropertiesSettings byMass(double mass) {
  MassPropertiesSettings s;
  s.mass = mass;
  return s;
}
MassPropertiesSettings byDensity(double density) {
  MassPropertiesSettings s;
  s.density = density;
  return s;
}

TriangleMesh unitCubeMesh() {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i) m.vertices.push_back(Vec3(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1));
  // Faces counter-clockwise seen from outside.
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangles.push_back({q[0], q[1], q[2]});
    m.triangles.push_back({q[0], q[2], q[3]});
  }
  return m;
}

TriangleMesh boxMesh(const Vec3& halfExtents, const Rigid& meshFromBox) {
  TriangleMesh m = unitCubeMesh();
  for (Vec3& v : m.vertices) v = meshFromBox * Vec3(v.cwiseProduct(halfExtents));
  return m;
}

// A latitude/longitude sphere (poles shared), counter-clockwise from outside.
TriangleMesh uvSphere(double radius, int slices, int stacks) {
  TriangleMesh m;
  m.vertices.push_back(Vec3(0, radius, 0));
  for (int i = 1; i < stacks; ++i) {
    const double theta = M_PI * i / stacks;
    for (int j = 0; j < slices; ++j) {
      const double phi = 2 * M_PI * j / slices;
      m.vertices.push_back(radius *
                           Vec3(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)));
    }
  }
  m.vertices.push_back(Vec3(0, -radius, 0));
  const int south = static_cast<int>(m.vertices.size()) - 1;
  auto ring = [&](int i, int j) { return 1 + (i - 1) * slices + (j % slices); };
  for (int j = 0; j < slices; ++j) m.triangles.push_back({0, ring(1, j + 1), ring(1, j)});
  for (int i = 1; i + 1 < stacks; ++i) {
    for (int j = 0; j < slices; ++j) {
      m.triangles.push_back({ring(i, j), ring(i, j + 1), ring(i + 1, j + 1)});
      m.triangles.push_back({ring(i, j), ring(i + 1, j + 1), ring(i + 1, j)});
    }
  }
  for (int j = 0; j < slices; ++j) m.triangles.push_back({south, ring(stacks - 1, j), ring(stacks - 1, j + 1)});
  return m;
}

TEST(MassProperties, AxisAlignedBoxMatchesClosedForm) {
  const Vec3 h(0.5, 1.0, 2.0);
  const MassProperties p = computeMassProperties(boxMesh(h, Rigid::Identity()), byDensity(3.0));
  const double volume = 8 * h.prod();
  EXPECT_NEAR(p.volume, volume, 1e-12);
  EXPECT_NEAR(p.mass, 3.0 * volume, 1e-12);
  EXPECT_LT(p.centerOfMassInMesh.norm(), 1e-12);
  const Vec3 size = 2 * h;
  const Vec3 expected = p.mass / 12.0 *
                        Vec3(size.y() * size.y() + size.z() * size.z(), size.x() * size.x() + size.z() * size.z(),
                             size.x() * size.x() + size.y() * size.y());
  EXPECT_LT((p.inertiaAboutCenterOfMass - Mat3(expected.asDiagonal())).norm(), 1e-10);
}

TEST(MassProperties, RotatedTranslatedBoxGivenTotalMass) {
  const Vec3 h(0.3, 0.7, 1.1);
  Rigid meshFromBox = Rigid::Identity();
  meshFromBox.linear() = Quat(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized())).toRotationMatrix();
  meshFromBox.translation() = Vec3(5.0, -3.0, 12.0);  // far from the origin: conditioning
  const MassProperties p = computeMassProperties(boxMesh(h, meshFromBox), byMass(2.5));
  EXPECT_NEAR(p.mass, 2.5, 1e-12);
  EXPECT_LT((p.centerOfMassInMesh - meshFromBox.translation()).norm(), 1e-10);
  const Vec3 size = 2 * h;
  const Vec3 diag = 2.5 / 12.0 *
                    Vec3(size.y() * size.y() + size.z() * size.z(), size.x() * size.x() + size.z() * size.z(),
                         size.x() * size.x() + size.y() * size.y());
  const Mat3 expected = meshFromBox.linear() * diag.asDiagonal() * meshFromBox.linear().transpose();
  EXPECT_LT((p.inertiaAboutCenterOfMass - expected).norm(), 1e-10);
  // Principal moments are the box's, ascending; the axes diagonalize the tensor.
  Vec3 sorted = diag;
  std::sort(sorted.data(), sorted.data() + 3);
  EXPECT_LT((p.principalMoments - sorted).norm(), 1e-10);
  const Mat3 d = p.principalAxesInMesh.transpose() * p.inertiaAboutCenterOfMass * p.principalAxesInMesh;
  EXPECT_LT((d - Mat3(p.principalMoments.asDiagonal())).norm(), 1e-10);
  EXPECT_NEAR(p.principalAxesInMesh.determinant(), 1.0, 1e-12);
}

TEST(MassProperties, FineSphereApproachesSolidSphere) {
  const double r = 0.8;
  const MassProperties p = computeMassProperties(uvSphere(r, 256, 128), byMass(1.0));
  EXPECT_NEAR(p.volume, 4.0 / 3.0 * M_PI * r * r * r, 2e-3 * p.volume);
  EXPECT_LT(p.centerOfMassInMesh.norm(), 1e-9);
  const double expected = 0.4 * r * r;
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(p.inertiaAboutCenterOfMass(i, i), expected, 2e-3 * expected);
  EXPECT_LT(std::abs(p.inertiaAboutCenterOfMass(0, 1)) + std::abs(p.inertiaAboutCenterOfMass(1, 2)), 1e-9);
}

// The project's own procedural meshes: makeBox exactly, makeIcosphere within its polyhedral error (an
// inscribed polyhedron: volume and moments slightly below the sphere's, converging with subdivision).
TEST(MassProperties, ProceduralBoxAndIcosphere) {
  const Vec3 h(0.2, 0.1, 0.3);
  const MassProperties box = computeMassProperties(makeBox(h), byMass(3.0));
  EXPECT_NEAR(box.volume, 8 * h.prod(), 1e-12);
  EXPECT_NEAR(box.inertiaAboutCenterOfMass(1, 1), 3.0 / 3.0 * (h.x() * h.x() + h.z() * h.z()), 1e-12);
  const double r = 0.5;
  double previousError = 1.0;
  for (int subdivisions : {2, 3, 4}) {
    const MassProperties ball = computeMassProperties(makeIcosphere(r, subdivisions), byMass(1.0));
    const double volumeError = 1.0 - ball.volume / (4.0 / 3.0 * M_PI * r * r * r);
    EXPECT_GT(volumeError, 0.0);
    EXPECT_LT(volumeError, previousError / 3.0);  // about 4x smaller per subdivision
    previousError = volumeError;
    EXPECT_LT(ball.centerOfMassInMesh.norm(), 1e-12);
    EXPECT_NEAR(ball.inertiaAboutCenterOfMass(0, 0), 0.4 * r * r, 2.0 * volumeError * 0.4 * r * r);
  }
  EXPECT_LT(previousError, 0.01);
}

// The body frame rule: the COM at the origin; an axis-aligned box keeps its axes (its principal axes are the
// mesh's), a rotated box gets its own axes back (the body frame undoes the rotation up to axis signs/order).
TEST(MassProperties, BodyFrameKeepsPrincipalMeshAxesAndRotatesOtherwise) {
  const Vec3 h(0.3, 0.7, 1.1);
  Rigid shifted = Rigid::Identity();
  shifted.translation() = Vec3(1.0, 2.0, -0.5);
  const BodyFrame aligned = bodyFrameOf(computeMassProperties(boxMesh(h, shifted), byMass(1.0)));
  EXPECT_TRUE(aligned.modelFromBody.linear().isIdentity(0.0));
  EXPECT_LT((aligned.modelFromBody.translation() - shifted.translation()).norm(), 1e-12);

  Rigid meshFromBox = shifted;
  meshFromBox.linear() = Quat(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized())).toRotationMatrix();
  const MassProperties p = computeMassProperties(boxMesh(h, meshFromBox), byMass(2.0));
  const BodyFrame frame = bodyFrameOf(p);
  EXPECT_LT((frame.modelFromBody.translation() - meshFromBox.translation()).norm(), 1e-10);
  EXPECT_NEAR(frame.modelFromBody.linear().determinant(), 1.0, 1e-12);
  // Diagonal in the body axes, with the box's moments.
  const Mat3& inertia = frame.inertiaInBody;
  EXPECT_LT(std::abs(inertia(0, 1)) + std::abs(inertia(0, 2)) + std::abs(inertia(1, 2)), 1e-10);
  Vec3 moments = frame.principalMoments();
  std::sort(moments.data(), moments.data() + 3);
  EXPECT_LT((moments - p.principalMoments).norm(), 1e-10);
  // Each body axis is one of the box's axes: |cos| = 1 with exactly one of them.
  const Mat3 boxFromBody = meshFromBox.linear().transpose() * frame.modelFromBody.linear();
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(boxFromBody.col(c).cwiseAbs().maxCoeff(), 1.0, 1e-9);
}

// A scene places the centre of mass at "position" and turns the mesh's own axes by "orientation".
TEST(MassProperties, WorldFromBodyAtPlacesCentreOfMassAndMeshAxes) {
  Rigid modelFromBody = Rigid::Identity();
  modelFromBody.linear() = Quat(Eigen::AngleAxisd(0.4, Vec3(0, 0, 1))).toRotationMatrix();
  modelFromBody.translation() = Vec3(0.1, -0.2, 0.3);  // the centre of mass in the mesh
  const Quat meshInWorld(Eigen::AngleAxisd(1.1, Vec3(1, 1, 0).normalized()));
  const Vec3 com(2.0, 3.0, -1.0);
  const Rigid worldFromBody = worldFromBodyAt(modelFromBody, com, meshInWorld);
  EXPECT_LT((worldFromBody.translation() - com).norm(), 1e-15);
  const Rigid worldFromModel = worldFromBody * modelFromBody.inverse();
  EXPECT_TRUE(worldFromModel.linear().isApprox(meshInWorld.toRotationMatrix(), 1e-14));
  EXPECT_LT((worldFromModel * modelFromBody.translation() - com).norm(), 1e-14);
}

TEST(MassProperties, RejectsBadInput) {
  TriangleMesh inverted = unitCubeMesh();
  for (auto& t : inverted.triangles) std::swap(t[1], t[2]);
  EXPECT_THROW(computeMassProperties(inverted, byMass(1.0)), Error);
  EXPECT_THROW(computeMassProperties(unitCubeMesh(), {}), Error);  // no mass, no density
  EXPECT_THROW(computeMassProperties(unitCubeMesh(), byDensity(-1.0)), Error);
  EXPECT_THROW(computeMassProperties(TriangleMesh{}, byMass(1.0)), Error);
  TriangleMesh bad = unitCubeMesh();
  bad.triangles[0][0] = 99;
  EXPECT_THROW(computeMassProperties(bad, byMass(1.0)), Error);
}

}  // namespace
}  // namespace sdfccd
