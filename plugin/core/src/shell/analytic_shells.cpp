/// @file
/// @brief Point shells on boxes, spheres and capsules (see analytic_shells.h).
#include "sdfccd/shell/analytic_shells.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "sdfccd/error.h"
#include "sdfccd/tolerances.h"

namespace sdfccd {
namespace {

const double kGoldenAngle = kPi * (3.0 - std::sqrt(5.0));  // Fibonacci spiral step (rad)

void checkSettings(const AnalyticShellSettings& settings, const char* what) {
  if (!(settings.spacing > 0.0) || !std::isfinite(settings.spacing) || settings.maxPoints < 12) {
    throw Error(std::string(what) + ": spacing must be positive and finite and maxPoints >= 12");
  }
}

int cellsAlong(double length, double spacing) {
  return std::max(1, static_cast<int>(std::ceil(length / spacing - tolerance::kCountRounding)));
}

/// Points of a Fibonacci spiral on the unit sphere; `upperHalfOnly` keeps z >= 0 (count = points there).
void addFibonacci(int count, bool upperHalfOnly, const Vec3& center, double radius, const Mat3& frame,
                  PointShell& out) {
  const int total = upperHalfOnly ? 2 * count : count;
  for (int k = 0; k < (upperHalfOnly ? count : total); ++k) {
    const double z = 1.0 - (2.0 * k + 1.0) / total;  // upper half first
    const double rho = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double angle = kGoldenAngle * k;
    const Vec3 normal = frame * Vec3(rho * std::cos(angle), rho * std::sin(angle), z);
    out.positions.push_back(center + radius * normal);
    out.normals.push_back(normal);
    // Point k sits in the middle of the band 1 - 2(k+1)/total < z < 1 - 2k/total: equal-area bands
    // (Archimedes), so each point stands for 4 pi r^2 / total.
    out.areas.push_back(4.0 * kPi * radius * radius / total);
  }
}

/// A frame whose third column is +-axis `axis` (sign) and whose columns are a rotation.
Mat3 frameAlong(int axis, double sign) {
  Mat3 frame = Mat3::Zero();
  frame(axis, 2) = sign;
  frame((axis + 1) % 3, 0) = 1.0;
  frame((axis + 2) % 3, 1) = sign;
  return frame;
}

}  // namespace

PointShell boxShell(const Vec3& halfExtents, const AnalyticShellSettings& settings) {
  checkSettings(settings, "boxShell");
  if (!halfExtents.allFinite() || !(halfExtents.minCoeff() > 0.0)) {
    throw Error("boxShell: the half extents must be positive and finite");
  }
  double spacing = settings.spacing;
  Eigen::Vector3i n;
  for (;;) {
    for (int i = 0; i < 3; ++i) n[i] = cellsAlong(2.0 * halfExtents[i], spacing);
    const double inner = double(std::max(0, n[0] - 1)) * std::max(0, n[1] - 1) * std::max(0, n[2] - 1);
    if (double(n[0] + 1) * (n[1] + 1) * (n[2] + 1) - inner <= settings.maxPoints) break;
    spacing *= 1.25;
  }
  // Each surface point carries its trapezoid-rule share of every face it lies on: the lattice step along the
  // face's two axes, halved at the face's borders, so each face's shares sum to its area exactly.
  const Vec3 step(2.0 * halfExtents[0] / n[0], 2.0 * halfExtents[1] / n[1], 2.0 * halfExtents[2] / n[2]);
  auto share = [&](const Eigen::Vector3i& index, int axis) {
    return (index[axis] == 0 || index[axis] == n[axis]) ? 0.5 * step[axis] : step[axis];
  };
  PointShell shell;
  for (int i = 0; i <= n[0]; ++i) {
    for (int j = 0; j <= n[1]; ++j) {
      for (int k = 0; k <= n[2]; ++k) {
        const Eigen::Vector3i index(i, j, k);
        Vec3 normal = Vec3::Zero();
        Vec3 position;
        for (int a = 0; a < 3; ++a) {
          position[a] = halfExtents[a] * (2.0 * index[a] / n[a] - 1.0);
          if (index[a] == 0) normal[a] = -1.0;
          if (index[a] == n[a]) {
            normal[a] = 1.0;
            position[a] = halfExtents[a];  // exactly on the face
          }
          if (index[a] == 0) position[a] = -halfExtents[a];
        }
        if (normal.isZero(0.0)) continue;  // an interior lattice point
        double area = 0.0;
        for (int a = 0; a < 3; ++a) {
          if (normal[a] != 0.0) area += share(index, (a + 1) % 3) * share(index, (a + 2) % 3);
        }
        shell.positions.push_back(position);
        shell.normals.push_back(normal.normalized());
        shell.areas.push_back(area);
      }
    }
  }
  return shell;
}

PointShell sphereShell(double radius, const AnalyticShellSettings& settings) {
  checkSettings(settings, "sphereShell");
  if (!(radius > 0.0) || !std::isfinite(radius)) throw Error("sphereShell: the radius must be positive and finite");
  const double wanted = std::ceil(4.0 * kPi * radius * radius / (settings.spacing * settings.spacing));
  const int count = static_cast<int>(std::max(12.0, std::min(wanted, double(settings.maxPoints))));
  PointShell shell;
  addFibonacci(count, false, Vec3::Zero(), radius, Mat3::Identity(), shell);
  return shell;
}

PointShell capsuleShell(double radius, double halfHeight, int axis, const AnalyticShellSettings& settings) {
  checkSettings(settings, "capsuleShell");
  if (!(radius > 0.0) || !std::isfinite(radius) || !(halfHeight >= 0.0) || !std::isfinite(halfHeight) || axis < 0 ||
      axis > 2) {
    throw Error("capsuleShell: radius must be positive, halfHeight >= 0 (both finite) and axis 0, 1 or 2");
  }
  double spacing = settings.spacing;
  int around = 0;
  int rings = 0;
  int perCap = 0;
  for (;;) {
    around = std::max(8, cellsAlong(2.0 * kPi * radius, spacing));
    rings = halfHeight > 0.0 ? cellsAlong(2.0 * halfHeight, spacing) + 1 : 1;  // the rims at +-halfHeight
    perCap = std::max(6, static_cast<int>(std::ceil(2.0 * kPi * radius * radius / (spacing * spacing))));
    if (double(around) * rings + 2.0 * perCap <= settings.maxPoints) break;
    spacing *= 1.25;
  }
  PointShell shell;
  // Ring points share the cylinder's area by the trapezoid rule along the axis (the rims get half a step);
  // the caps' spiral points carry 2 pi r^2 / perCap each (see addFibonacci).
  const double ringArea = rings > 1 ? 2.0 * kPi * radius / around * 2.0 * halfHeight / (rings - 1) : 0.0;
  const int u = (axis + 1) % 3;
  const int v = (axis + 2) % 3;
  for (int r = 0; r < rings; ++r) {
    const double along = rings > 1 ? -halfHeight + 2.0 * halfHeight * r / (rings - 1) : 0.0;
    for (int k = 0; k < around; ++k) {
      const double angle = 2.0 * kPi * k / around;
      Vec3 normal = Vec3::Zero();
      normal[u] = std::cos(angle);
      normal[v] = std::sin(angle);
      Vec3 position = radius * normal;
      position[axis] = along;
      shell.positions.push_back(position);
      shell.normals.push_back(normal);
      shell.areas.push_back((r == 0 || r == rings - 1) ? 0.5 * ringArea : ringArea);
    }
  }
  // The caps' spirals stop short of their rims (z > 0), which the rings already hold.
  for (double sign : {1.0, -1.0}) {
    Vec3 center = Vec3::Zero();
    center[axis] = sign * halfHeight;
    addFibonacci(perCap, true, center, radius, frameAlong(axis, sign), shell);
  }
  // halfHeight = 0: one ring on the equator of a sphere the two half spirals already cover; it has no band of
  // its own, so the sphere's area is shared evenly by all points instead.
  if (rings == 1) assignUniformAreas(shell, 4.0 * kPi * radius * radius);
  return shell;
}

}  // namespace sdfccd
