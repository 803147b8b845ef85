/// @file
/// @brief BodyModel: everything one rigid body shape needs for point-vs-field CCD (paper Section 5):
/// the point shell and its tree, the distance field and its octree, mass properties and the mesh.
///
/// @details In the paper's simulations "each bunny carries a pointshell and a signed distance field": every
/// pair is checked twice, each body in each role. A model is immutable once built and shared through
/// std::shared_ptr<const BodyModel> by any number of shapes and bodies; reading it from many threads is
/// safe.
///
/// Frames: the model's *body frame* is the frame Bullet simulates (centre of mass at the origin, axes along
/// the principal axes of inertia unless the mesh's own axes already are principal). The mesh and the shell
/// are stored in the body frame, the field too when built here (see bodyFromField()); `modelFromBody` maps body
/// coordinates back to the mesh file's coordinates (after scaling), so a scene's pose of the mesh is worldFromModel =
/// worldFromBody * modelFromBody^-1.
///
/// Point areas (stiffness per unit area): every shell has them; a shell loaded from a file or the cache,
/// which stores none, gets its mesh's barycentric vertex areas (vertex shells) or the mesh's area shared
/// evenly (assignUniformAreas).
///
/// Uniform scaling is baked in at build time (settings.scale): the field and the shell are built from the
/// scaled mesh and the cache key includes the scale. The Bullet shape rejects setLocalScaling.
///
/// Cache: buildFromMeshFile() keeps the field and the shell in the model cache (model_cache.h), keyed by the mesh
/// file's bytes and the parameters (resolution, padding, points, scale, format version).
///
/// Bullet-free: the Bullet plugin wraps a model in an SdfccdShape; haptics and the tool use it directly.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "sdfccd/field/grid_field.h"
#include "sdfccd/math_types.h"
#include "sdfccd/mesh/mass_properties.h"
#include "sdfccd/mesh/triangle_mesh.h"
#include "sdfccd/progress.h"
#include "sdfccd/shell/point_shell.h"
#include "sdfccd/shell/point_tree.h"

namespace sdfccd {

/// How a model is built from a mesh.
struct BodyModelSettings {
  int resolution = 128;       ///< SDF cells along the longest side of the mesh's box
  int padding = 4;            ///< SDF cells added around the mesh's box on every side
  int points = 0;             ///< shell points by particle repulsion; 0: the mesh's vertices
  double scale = 1.0;         ///< uniform scale applied to the mesh first (> 0)
  int threads = 0;            ///< worker threads of the builds (0: all cores)
  std::string cacheDir;       ///< buildFromMeshFile's model cache folder (model_cache.h); empty: no cache
  ProgressCallback progress;  ///< optional, fraction of the SDF build done
  /// A box primitive (half extents in model units, before `scale`): with points == 0 its shell is sampled on
  /// its surface at max(1 cell, thinnest side / 16), edges and corners included, not just its 8 corners
  /// (docs/design/contact-response.md, default shells for primitives).
  std::optional<Vec3> boxHalfExtents;
};

class BodyModel {
 public:
  /// Builds a model from a mesh given in model units (scale applied here). Throws sdfccd::Error on a bad mesh
  /// (not closed, zero volume) or bad settings.
  static std::shared_ptr<const BodyModel> buildFromMesh(const TriangleMesh& meshInModel,
                                                        const BodyModelSettings& settings);
  /// Loads the mesh file (loadMeshFile, mesh_file.h) and builds, or loads from the cache when an entry for
  /// the same file content and parameters exists. Throws sdfccd::Error naming the file on failure.
  static std::shared_ptr<const BodyModel> buildFromMeshFile(const std::string& meshPath,
                                                            const BodyModelSettings& settings);
  /// Assembles a model from files: the mesh (for mass properties and rendering), a field (.sdf/.sdfgen) and
  /// a shell (.ply/.csv), all three in the mesh's model frame, scaled by settings.scale. Throws sdfccd::Error.
  static std::shared_ptr<const BodyModel> loadFromFiles(const std::string& meshPath, const std::string& sdfPath,
                                                        const std::string& shellPath,
                                                        const BodyModelSettings& settings);

  const TriangleMesh& meshInBody() const { return m_meshInBody; }
  const PointShell& shell() const { return m_tree.shell(); }  ///< body frame
  const PointTree& tree() const { return m_tree; }
  const GridField& field() const { return *m_field; }
  /// Maps field coordinates to body coordinates: identity for models built here; the model-to-body map for
  /// fields loaded from files (a grid cannot be rotated, so the field keeps the mesh file's frame).
  const Rigid& bodyFromField() const { return m_bodyFromField; }
  /// Mass properties at unit density, in the body frame (COM at the origin, diagonal inertia).
  const MassProperties& unitDensityMassProperties() const { return m_mass; }
  /// Principal moments of inertia for a total mass (kg m^2).
  Vec3 principalInertia(double mass) const { return m_mass.principalMoments * (mass / m_mass.mass); }
  const Rigid& modelFromBody() const { return m_modelFromBody; }
  double cellSize() const { return m_field->spacing(); }  ///< model units
  /// The axis-aligned box of the mesh in the body frame.
  const Box3& boundsInBody() const { return m_boundsInBody; }

 private:
  BodyModel() = default;
  static std::shared_ptr<BodyModel> assemble(const TriangleMesh& meshInModel, double scale);

  TriangleMesh m_meshInBody;
  PointTree m_tree;
  std::unique_ptr<GridField> m_field;
  MassProperties m_mass;
  Rigid m_modelFromBody = Rigid::Identity();
  Rigid m_bodyFromField = Rigid::Identity();
  Box3 m_boundsInBody;
};

}  // namespace sdfccd
