/// @file
/// @brief ConvexPolytopeField against BoxField (a cube's triangles grown by a radius is the box field minus the
/// radius, exactly) and TriangleSetField against brute force (the minimum over the triangles of a densely
/// sampled triangle, and the segment's intervals against dense sampling along t).
#include "sdfccd/field/polytope_fields.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sdfccd/error.h"
#include "sdfccd/field/analytic_fields.h"
#include "sdfccd/mesh/procedural_meshes.h"

namespace sdfccd {
namespace {

SegmentCcdSettings polytopeAll(double sigma) {
  SegmentCcdSettings s;
  s.sigma = sigma;
  s.mode = CcdMode::AllIntervals;
  return s;
}

bool insideIntervals(const IntervalList& list, double t, double slack) {
  for (std::size_t i = 0; i < list.size(); ++i) {
    if (t >= list[i].begin - slack && t <= list[i].end + slack) return true;
  }
  return false;
}

/// Every t sampled densely is inside the query's intervals iff phi - sigma <= 0 there (up to a band of 1e-9
/// of phi, where rounding decides), and the first hit matches the first sample inside.
template <class Field>
void expectIntervalsMatchSampling(const Field& field, const Vec3& p0, const Vec3& p1, double sigma) {
  SegmentCcdResult r;
  field.intersectSegment(p0, p1, polytopeAll(sigma), r);
  const int n = 4000;
  double firstSample = -1.0;
  for (int i = 0; i <= n; ++i) {
    const double t = double(i) / n;
    const double f = field.distance(p0 + t * (p1 - p0)) - sigma;
    if (f < -1e-9) {
      EXPECT_TRUE(insideIntervals(r.intervals, t, 1e-12)) << "t " << t << " f " << f;
      if (firstSample < 0.0) firstSample = t;
    }
    if (f > 1e-9) {
      EXPECT_FALSE(insideIntervals(r.intervals, t, 0.0)) << "t " << t << " f " << f;
    }
  }
  if (firstSample >= 0.0) {
    ASSERT_TRUE(r.hit());
    EXPECT_LE(r.fraction, firstSample + 1e-12);
    EXPECT_GE(r.fraction, firstSample - 1.0 / n - 1e-9);  // touching is within 1e-12 of sigma
    // At a crossing the field equals sigma (to the bisection's last bit).
    if (r.state == SegmentState::Hit) {
      EXPECT_NEAR(field.distance(r.point), sigma, 1e-9);
    }
  }
}

TEST(ConvexPolytopeField, CubeGrownByRadiusIsTheBoxFieldMinusRadius) {
  const Vec3 h(0.3, 0.2, 0.5);
  const TriangleMesh cube = makeBox(h);
  const double radius = 0.04;
  const ConvexPolytopeField polytope(cube.vertices, cube.triangles, radius);
  const BoxField box(h);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    EXPECT_NEAR(polytope.distance(p), box.distance(p) - radius, 1e-12) << p.transpose();
    if (std::abs(box.distance(p)) > 1e-6) {
      EXPECT_TRUE(polytope.gradient(p).isApprox(box.gradient(p), 1e-9)) << p.transpose();
    }
  }
  for (int i = 0; i < 200; ++i) {
    const Vec3 p0(u(rng), u(rng), u(rng));
    const Vec3 p1(u(rng), u(rng), u(rng));
    expectIntervalsMatchSampling(polytope, p0, p1, 0.01);
  }
}

TEST(ConvexPolytopeField, FallingPointHitsTheTopAtTheAnalyticFraction) {
  const TriangleMesh cube = makeBox(Vec3(1.0, 1.0, 1.0));
  const ConvexPolytopeField polytope(cube.vertices, cube.triangles, 0.1);
  SegmentCcdResult r;
  SegmentCcdSettings s;
  s.sigma = 0.05;
  // From y = 3 to y = 0: phi = y - 1.1 reaches 0.05 at y = 1.15, t = (3 - 1.15) / 3.
  polytope.intersectSegment(Vec3(0.2, 3.0, -0.3), Vec3(0.2, 0.0, -0.3), s, r);
  ASSERT_EQ(r.state, SegmentState::Hit);
  EXPECT_NEAR(r.fraction, 1.85 / 3.0, 1e-11);  // touching is within 1e-12 (x the coordinates' size)
  EXPECT_TRUE(r.normal.isApprox(Vec3::UnitY(), 1e-12));
  EXPECT_TRUE(r.intervals.empty());  // FirstHit
  polytope.intersectSegment(Vec3(0.2, 0.5, 0.0), Vec3(0.2, 3.0, 0.0), s, r);
  EXPECT_EQ(r.state, SegmentState::StartsInside);
  EXPECT_NEAR(r.depth, -0.5 - 0.1 - 0.05, 1e-14);
}

TEST(ConvexPolytopeField, RejectsBadInput) {
  const TriangleMesh cube = makeBox(Vec3(1.0, 1.0, 1.0));
  EXPECT_THROW(ConvexPolytopeField(cube.vertices, {}, 0.0), Error);
  EXPECT_THROW(ConvexPolytopeField(cube.vertices, cube.triangles, -1.0), Error);
  EXPECT_THROW(ConvexPolytopeField(cube.vertices, {{0, 1, 99}}, 0.0), Error);
  EXPECT_THROW(ConvexPolytopeField(cube.vertices, {{0, 0, 1}}, 0.0), Error);
  SegmentCcdResult r;
  ConvexPolytopeField(cube.vertices, cube.triangles, 0.0)
      .intersectSegment(Vec3(std::nan(""), 0, 0), Vec3::Zero(), SegmentCcdSettings{}, r);
  EXPECT_EQ(r.state, SegmentState::Failed);
}

/// The brute-force distance to one triangle: the nearest of a dense barycentric lattice (within h of exact).
double latticeDistance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, int n) {
  double best = 1e300;
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; i + j <= n; ++j) {
      const Vec3 q = a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n);
      best = std::min(best, (p - q).norm());
    }
  }
  return best;
}

TEST(TriangleSetField, DistanceIsTheNearestTriangleUnsigned) {
  // A tilted open surface: two triangles of a ramp and a lone vertical one.
  const std::vector<Vec3> v = {Vec3(0, 0, 0),     Vec3(1, 0.3, 0),   Vec3(1, 0.3, 1),  Vec3(0, 0, 1),
                               Vec3(0.5, 0, 0.5), Vec3(0.5, 1, 0.5), Vec3(0.5, 0, 1.5)};
  const TriangleSetField field(v, {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}}, 0.0);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.5, 1.5);
  const int n = 120;
  for (int i = 0; i < 200; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const double brute = std::min({latticeDistance(p, v[0], v[1], v[2], n), latticeDistance(p, v[0], v[2], v[3], n),
                                   latticeDistance(p, v[4], v[5], v[6], n)});
    const double exact = field.distance(p);
    EXPECT_LE(exact, brute + 1e-12);
    EXPECT_GE(exact, brute - 1.5 / n);  // the lattice is within its spacing of every point
  }
  for (int i = 0; i < 200; ++i) {
    expectIntervalsMatchSampling(field, Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng)), 0.02);
  }
}

TEST(TriangleSetField, NormalsFaceTheOutsidePointAndThicknessHoldsWhatSankIn) {
  const std::vector<Vec3> quad = {Vec3(-1, 0, -1), Vec3(1, 0, -1), Vec3(1, 0, 1), Vec3(-1, 0, 1)};
  const std::vector<TriangleIndices> down = {{0, 2, 1}, {0, 3, 2}};  // facing down (clockwise from above)
  const TriangleSetField above(quad, down, 0.0, 0.01, Vec3(0, 5, 0));
  SegmentCcdResult r;
  SegmentCcdSettings s;  // sigma 0: the point reaches the surface itself
  above.intersectSegment(Vec3(0.1, 2.0, 0.2), Vec3(0.1, -2.0, 0.2), s, r);
  ASSERT_EQ(r.state, SegmentState::Hit);
  EXPECT_NEAR(r.fraction, 0.5, 1e-11);
  EXPECT_TRUE(r.normal.isApprox(Vec3::UnitY(), 1e-12)) << "turned to the outside point, whatever the winding";
  // 20 m/s for a 1/60 s step through a wall of zero thickness: a hit.
  above.intersectSegment(Vec3(0.0, 0.1, 0.0), Vec3(0.0, -0.23, 0.0), s, r);
  EXPECT_EQ(r.state, SegmentState::Hit);
  // Sunk 4 mm (within the 1 cm thickness): inside, pushed up; 2 cm below: the wall's other side, no contact.
  EXPECT_NEAR(above.distance(Vec3(0.3, -0.004, 0.3)), -0.004, 1e-15);
  EXPECT_TRUE(above.gradient(Vec3(0.3, -0.004, 0.3)).isApprox(Vec3::UnitY(), 1e-12));
  above.intersectSegment(Vec3(0.3, -0.004, 0.3), Vec3(0.3, -0.003, 0.3), s, r);
  EXPECT_EQ(r.state, SegmentState::StartsInside);
  EXPECT_NEAR(r.depth, -0.004, 1e-15);
  EXPECT_NEAR(above.distance(Vec3(0.3, -0.02, 0.3)), 0.02, 1e-15);
  above.intersectSegment(Vec3(0.3, -0.02, 0.3), Vec3(0.3, -0.5, 0.3), s, r);
  EXPECT_EQ(r.state, SegmentState::Separated);
  // The same quad seen from below: the normal points down.
  const TriangleSetField below(quad, down, 0.0, 0.01, Vec3(0, -5, 0));
  below.intersectSegment(Vec3(0.1, -2.0, 0.2), Vec3(0.1, 2.0, 0.2), s, r);
  ASSERT_EQ(r.state, SegmentState::Hit);
  EXPECT_TRUE(r.normal.isApprox(-Vec3::UnitY(), 1e-12));
  // Passing beside it: no contact. Intervals with a thickness still match sampling.
  above.intersectSegment(Vec3(1.2, 1.0, 0.0), Vec3(1.2, -1.0, 0.0), s, r);
  EXPECT_EQ(r.state, SegmentState::Separated);
  expectIntervalsMatchSampling(above, Vec3(-0.5, 0.3, 0.1), Vec3(0.4, -0.1, 0.2), 0.005);
  expectIntervalsMatchSampling(above, Vec3(0.9, 0.01, 0.1), Vec3(1.1, -0.05, 0.2), 0.0);
  EXPECT_THROW(TriangleSetField({Vec3::Zero(), Vec3::UnitX(), Vec3(2, 0, 0)}, {{0, 1, 2}}, 0.0), Error);
  EXPECT_THROW(TriangleSetField(quad, down, 0.0, -1.0), Error);
}

// Cylinder: the closed form min(max(qx, qy), 0) + |max(q, 0)| with q = (rho - r, |y| - h), minus the rounding.
TEST(RevolvedConvexField, CylinderMatchesTheClosedForm) {
  const double r = 0.3, h = 0.1, rounding = 0.02;
  for (int axis = 0; axis < 3; ++axis) {
    const RevolvedConvexField field = cylinderField(r, h, axis, rounding);
    std::mt19937 rng(5 + axis);
    std::uniform_real_distribution<double> u(-0.6, 0.6);
    for (int i = 0; i < 2000; ++i) {
      const Vec3 p(u(rng), u(rng), u(rng));
      Vec3 radial = p;
      radial[axis] = 0.0;
      const Eigen::Vector2d q(radial.norm() - r, std::abs(p[axis]) - h);
      const double exact = std::min(std::max(q.x(), q.y()), 0.0) + q.cwiseMax(0.0).norm() - rounding;
      EXPECT_NEAR(field.distance(p), exact, 1e-14) << p.transpose();
      // The gradient is the distance's: a central difference (away from the creases).
      const double e = 1e-6;
      Vec3 numeric;
      for (int k = 0; k < 3; ++k) {
        numeric[k] = (field.distance(p + e * Vec3::Unit(k)) - field.distance(p - e * Vec3::Unit(k))) / (2 * e);
      }
      if (std::abs(q.x() - q.y()) > 1e-3 && std::abs(q.x()) > 1e-3 && std::abs(q.y()) > 1e-3 && radial.norm() > 1e-3) {
        EXPECT_TRUE(field.gradient(p).isApprox(numeric, 1e-5)) << p.transpose();
      }
    }
    for (int i = 0; i < 100; ++i) {
      expectIntervalsMatchSampling(field, Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng)), 0.01);
    }
  }
}

// Cone: against brute force, the nearest of dense samples of its surface (lateral and base), signed by inside.
TEST(RevolvedConvexField, ConeMatchesBruteForce) {
  const double r = 0.2, height = 0.3;
  const RevolvedConvexField field = coneField(r, height, 1, 0.0);
  std::vector<Vec3> surface;
  const int n = 200;
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j < 4 * n; ++j) {
      const double s = double(i) / n, angle = 2 * M_PI * j / (4 * n);
      const Vec3 dir(std::cos(angle), 0.0, std::sin(angle));
      surface.push_back(s * r * dir + Vec3(0, 0.5 * height - s * height, 0));  // lateral, apex to rim
      surface.push_back(s * r * dir + Vec3(0, -0.5 * height, 0));              // base disc
    }
  }
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.35, 0.35);
  const double spacing = 2 * M_PI * r / (4 * n) + std::hypot(r, height) / n;
  for (int i = 0; i < 300; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    double brute = 1e300;
    for (const Vec3& q : surface) brute = std::min(brute, (p - q).norm());
    const double rho = std::hypot(p.x(), p.z());
    const bool inside = p.y() >= -0.5 * height && rho <= r * (0.5 * height - p.y()) / height;
    EXPECT_NEAR(field.distance(p), inside ? -brute : brute, spacing) << p.transpose();
  }
  for (int i = 0; i < 100; ++i) {
    expectIntervalsMatchSampling(field, Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng)), 0.005);
  }
  EXPECT_THROW(RevolvedConvexField({{0, 1}, {1, 0}}, 1, 0.0), Error);
  EXPECT_THROW(RevolvedConvexField({{0.1, 1}, {1, 0}, {0, 0}}, 1, 0.0), Error);
  EXPECT_THROW(coneField(0.2, 0.3, 3, 0.0), Error);
}

}  // namespace
}  // namespace sdfccd
