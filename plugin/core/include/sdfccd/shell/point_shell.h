/// @file
/// @brief PointShell: the points (with outward normals) that represent one body in point-vs-field CCD
/// (paper Section 3.3 and Section 5: "point-sampled objects").
///
/// @details A shell lives in its body's frame. It comes from a mesh in one of two ways:
/// - shellFromVertices(): the mesh vertices, each with its area-weighted vertex normal;
/// - sampleShell(): N points spread evenly over the surface by particle repulsion (Turk, "Re-tiling polygonal
///   surfaces", SIGGRAPH 1992, the method the paper's point shells are made with): area-weighted random
///   samples (fixed seed) relax under a short-range repulsion, each move kept in the tangent plane and the
///   point projected back onto the mesh (closest point), so every point lies ON the mesh and carries the
///   normal of the face it lies on. Iterations are Jacobi steps (all points move from the old positions), so
///   the result does not depend on the thread count.
/// Shell files: ascii PLY (x y z nx ny nz per vertex) or CSV ("x,y,z,nx,ny,nz" header), chosen by extension.
///
/// Point areas (stiffness per unit area, k_i = k_A A_i: docs/design/contact-response.md): every builder fills
/// `areas`, the surface area each point stands for, summing to the surface's area:
/// - shellFromVertices(): the barycentric vertex area, 1/3 of the areas of the incident triangles;
/// - sampleShell(): A_total / N (particle repulsion spreads the points evenly), A_total the usable faces' area;
/// - boxShell(), sphereShell(), capsuleShell() (analytic_shells.h): exact per-point shares of the closed-form area.
/// Shell files do not store areas (the formats stay as they are): loadShell()/parseShell() return `areas` empty,
/// and whoever knows the surface (the body-model builder, with the mesh's TriangleMesh::area()) calls
/// assignUniformAreas(). An empty `areas` means "unknown"; nothing else reads them yet.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sdfccd/math_types.h"
#include "sdfccd/mesh/triangle_mesh.h"
#include "sdfccd/progress.h"

namespace sdfccd {

/// Points with unit outward normals, in the body (shell) frame.
struct PointShell {
  std::vector<Vec3> positions;  ///< body frame (model units)
  std::vector<Vec3> normals;    ///< unit outward normals, body frame; same count as positions
  std::vector<double> areas;    ///< surface area per point (model units^2, m^2 in SI scenes); empty: unknown

  std::size_t size() const { return positions.size(); }
  bool empty() const { return positions.empty(); }
  /// True when every point has an area (`areas` has one entry per point).
  bool hasAreas() const { return !positions.empty() && areas.size() == positions.size(); }
  /// Sum of `areas` (model units^2); 0 when they are unknown.
  double totalArea() const;
  /// Throws sdfccd::Error unless counts match, everything is finite and every normal has unit length (1e-6);
  /// `areas`, if not empty, must have one entry per point, each positive and finite.
  void validate() const;
};

/// The curvature of `shell` at each point (rad per model unit): the largest angle between the point's normal and
/// a neighbour's, over the neighbour's distance, among the neighbours within 1.5 point spacings (the spacing from
/// the mean area per point when the shell has areas, else from its bounding box's surface). Points with no
/// neighbour get 0. Which surface of a pair gives a contact's normal (response/contact_normal.h).
std::vector<double> shellCurvatures(const PointShell& shell);

/// Gives every point the area totalArea / N (model units^2): the rule for evenly sampled shells, and what the
/// body-model builder calls on a loaded shell with its mesh's TriangleMesh::area(). Throws sdfccd::Error (one
/// line) on an empty shell or a totalArea that is not positive and finite.
void assignUniformAreas(PointShell& shell, double totalArea);

/// The mesh's vertices with area-weighted vertex normals (sum of the incident faces' area vectors,
/// normalized) and barycentric areas (1/3 of the incident faces' areas). Vertices whose area vectors sum to
/// zero have no normal and are left out (with their area: then the areas sum to less than the mesh's area;
/// on a closed, non-degenerate mesh this never happens). Throws sdfccd::Error if nothing is left.
PointShell shellFromVertices(const TriangleMesh& mesh);

/// Settings of sampleShell.
struct ShellSamplingSettings {
  int points = 1000;           ///< number of points N (>= 1)
  int iterations = 20;         ///< repulsion iterations (0: the area-weighted random samples as they are)
  std::uint64_t seed = 12345;  ///< seed of the initial random samples (the result is deterministic)
  double stepScale = 0.1;      ///< step of one iteration, times the repulsion radius per unit force
  int threads = 1;             ///< worker threads (0: all cores); the result does not depend on it
  ProgressCallback progress;   ///< optional, called once per iteration
};

/// N points spread evenly over the mesh surface (see the file comment), each with the area A / N, A the
/// area of the faces of non-zero area. Repulsion radius r = 2 sqrt(A / N). Throws sdfccd::Error on an empty mesh, a
/// mesh of zero area, non-finite vertices or absurd settings.
PointShell sampleShell(const TriangleMesh& mesh, const ShellSamplingSettings& settings = {});

/// Writes the shell as ascii PLY (".ply") or CSV (".csv"), by the extension (case-insensitive), atomically:
/// positions and normals only (areas are not stored).
/// Throws sdfccd::Error on another extension, an invalid shell or a write failure.
void saveShell(const PointShell& shell, const std::string& path);

/// Reads a shell written by saveShell (or any ascii PLY whose vertex element has x y z nx ny nz). Normals
/// are normalized; `areas` stays empty (see assignUniformAreas). Throws sdfccd::Error (one line naming the file and
/// line) on a missing file, another format, a truncated file, wrong counts, non-numbers, NaN/inf or zero-length
/// normals.
PointShell loadShell(const std::string& path);
/// loadShell from memory: `text` is a file's content; `name` (a path or file name) picks the format by its
/// extension and names the input in errors. Same checks, same errors.
PointShell parseShell(const std::string& text, const std::string& name);

}  // namespace sdfccd
