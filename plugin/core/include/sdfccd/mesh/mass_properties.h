/// @file
/// @brief Mass, centre of mass and inertia tensor of a closed triangle mesh from its volume integrals.
///
/// @details The rigid bodies of the Bullet plugin (paper Section 5) need the mass properties of the solid the
/// mesh encloses, not of its bounding box. Each triangle forms a signed tetrahedron with the origin; summing
/// the tetrahedra's volume, first moments and second moments (covariance) gives the solid's integrals by the
/// divergence theorem, exactly for any closed, consistently oriented mesh (holes make it approximate).
///
/// Edge-case policy: a mesh whose signed volume is not positive (open, inside-out or flat) is rejected with
/// sdfccd::Error; the caller repairs/orients it first (repairMesh in triangle_mesh.h).
#pragma once

#include "sdfccd/math_types.h"
#include "sdfccd/mesh/triangle_mesh.h"

namespace sdfccd {

/// How the mass is given.
struct MassPropertiesSettings {
  double density = 0.0;  ///< kg/m^3 (model units^3); used when mass <= 0
  double mass = 0.0;     ///< kg; when > 0 it is the total mass and the density follows from the volume
};

/// The mass properties of a solid.
struct MassProperties {
  double volume = 0.0;                           ///< model units^3
  double mass = 0.0;                             ///< kg
  Vec3 centerOfMassInMesh = Vec3::Zero();        ///< centre of mass in the mesh's frame (model units)
  Mat3 inertiaAboutCenterOfMass = Mat3::Zero();  ///< inertia tensor about the COM, mesh axes (kg m^2)
  Mat3 principalAxesInMesh = Mat3::Identity();   ///< columns: principal axes (a rotation, det = +1)
  Vec3 principalMoments = Vec3::Zero();          ///< diagonal inertia in the principal axes (kg m^2), ascending
};

/// Computes the mass properties of the solid bounded by `mesh`. Throws sdfccd::Error if the mesh is empty,
/// has non-finite coordinates or out-of-range indices, its volume is not positive, or neither a positive
/// mass nor a positive density is given.
MassProperties computeMassProperties(const TriangleMesh& mesh, const MassPropertiesSettings& settings);

/// The frame a rigid body simulation moves (Bullet's body frame, paper Section 5), derived from mass properties.
struct BodyFrame {
  Rigid modelFromBody = Rigid::Identity();  ///< maps body coordinates to the mesh's (model units)
  Mat3 inertiaInBody = Mat3::Zero();        ///< inertia about the COM in body axes (kg m^2), diagonal up to rounding
  /// The diagonal of inertiaInBody (kg m^2): the principal moments in the order of the body axes.
  Vec3 principalMoments() const { return inertiaInBody.diagonal(); }
};

/// The body frame rule, the one place it is decided (BodyModel and the CLI's run folders both call it):
/// origin at the centre of mass; axes along the principal axes of inertia, unless the mesh's own axes already
/// are principal (off-diagonal inertia under 1e-9 of the trace) — symmetric shapes have ill-defined principal
/// axes, and a box or a sphere should not come out arbitrarily rotated.
BodyFrame bodyFrameOf(const MassProperties& inModel);

/// Where a scene puts a body: `centerOfMassInWorld` places the centre of mass, `modelOrientationInWorld`
/// turns the mesh's own axes (the body axes follow through modelFromBody). Scenes, the simulation and run
/// folders all place bodies with it.
Rigid worldFromBodyAt(const Rigid& modelFromBody, const Vec3& centerOfMassInWorld, const Quat& modelOrientationInWorld);

}  // namespace sdfccd
