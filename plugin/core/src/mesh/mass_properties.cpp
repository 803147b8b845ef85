/// @file
/// @brief Volume integrals of a closed triangle mesh (see mass_properties.h).
#include "sdfccd/mesh/mass_properties.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <string>

#include "sdfccd/error.h"
#include "sdfccd/tolerances.h"

namespace sdfccd {

MassProperties computeMassProperties(const TriangleMesh& mesh, const MassPropertiesSettings& settings) {
  checkMesh(mesh, "mass properties");
  if (!(settings.mass > 0.0) && !(settings.density > 0.0)) {
    throw Error("mass properties: give a positive mass or density (mass " + std::to_string(settings.mass) +
                ", density " + std::to_string(settings.density) + ")");
  }
  if (!std::isfinite(settings.mass) || !std::isfinite(settings.density)) {
    throw Error("mass properties: mass and density must be finite");
  }
  // Reference point near the mesh: keeps the tetrahedra small and the sums well conditioned for meshes far
  // from the origin.
  const Vec3 reference = mesh.vertices.front();

  // Canonical second-moment (covariance) matrix of the unit tetrahedron (0, e1, e2, e3): int x_i x_j dV.
  // Eigen has no volume-integral routine, hence this by-hand sum over signed tetrahedra.
  Mat3 canonical;
  canonical << 2.0, 1.0, 1.0, 1.0, 2.0, 1.0, 1.0, 1.0, 2.0;
  canonical /= 120.0;

  double volume = 0.0;
  Vec3 firstMoment = Vec3::Zero();
  Mat3 covariance = Mat3::Zero();
  for (const auto& tri : mesh.triangles) {
    Mat3 a;
    a.col(0) = mesh.vertices[tri[0]] - reference;
    a.col(1) = mesh.vertices[tri[1]] - reference;
    a.col(2) = mesh.vertices[tri[2]] - reference;
    const double det = a.determinant();  // 6 x signed volume of the tetrahedron (reference, v0, v1, v2)
    volume += det / 6.0;
    firstMoment += det / 24.0 * (a.col(0) + a.col(1) + a.col(2));
    covariance += det * a * canonical * a.transpose();
  }
  if (!(volume > 0.0) || !std::isfinite(volume)) {
    throw Error("mass properties: the mesh's signed volume is " + std::to_string(volume) +
                " (must be closed and oriented outward)");
  }

  MassProperties out;
  out.volume = volume;
  const double density = settings.mass > 0.0 ? settings.mass / volume : settings.density;
  out.mass = density * volume;
  const Vec3 centerFromReference = firstMoment / volume;
  out.centerOfMassInMesh = reference + centerFromReference;
  // Covariance about the centre of mass (parallel axis theorem), scaled by the density.
  const Mat3 covarianceAboutCom =
      density * (covariance - volume * centerFromReference * centerFromReference.transpose());
  out.inertiaAboutCenterOfMass = covarianceAboutCom.trace() * Mat3::Identity() - covarianceAboutCom;

  const Eigen::SelfAdjointEigenSolver<Mat3> solver(out.inertiaAboutCenterOfMass);
  out.principalMoments = solver.eigenvalues();
  out.principalAxesInMesh = solver.eigenvectors();
  if (out.principalAxesInMesh.determinant() < 0.0) out.principalAxesInMesh.col(2) *= -1.0;
  return out;
}

BodyFrame bodyFrameOf(const MassProperties& inModel) {
  const Mat3& inertia = inModel.inertiaAboutCenterOfMass;
  const double offDiagonal = std::abs(inertia(0, 1)) + std::abs(inertia(0, 2)) + std::abs(inertia(1, 2));
  BodyFrame frame;
  frame.modelFromBody.translation() = inModel.centerOfMassInMesh;
  if (offDiagonal > tolerance::kPrincipalAxesTolerance * inertia.trace())
    frame.modelFromBody.linear() = inModel.principalAxesInMesh;
  const Mat3 bodyFromModelRotation = frame.modelFromBody.linear().transpose();
  frame.inertiaInBody = bodyFromModelRotation * inertia * bodyFromModelRotation.transpose();
  return frame;
}

Rigid worldFromBodyAt(const Rigid& modelFromBody, const Vec3& centerOfMassInWorld,
                      const Quat& modelOrientationInWorld) {
  Rigid worldFromBody = Rigid::Identity();
  worldFromBody.linear() = modelOrientationInWorld.toRotationMatrix() * modelFromBody.linear();
  worldFromBody.translation() = centerOfMassInWorld;
  return worldFromBody;
}

}  // namespace sdfccd
