/// @file
/// @brief FieldCullingBounds: what the point tree must know about a field to cull nodes without ever missing a
/// contact (paper Section 3.3).
///
/// @details The paper culls a node of radius rho when its centre's segment does not reach phi = sigma + rho.
/// That is exact when phi is 1-Lipschitz, as a true distance is. A grid field is a trilinear interpolant,
/// whose gradient can exceed 1 (up to sqrt(3) for exact node distances, more for noisy grids), and its
/// segment query sees no contact outside its box. So a grid field reports
/// - `lipschitz`: the largest gradient norm of the interpolant over all cells (bounded per cell from the
///   12 edge differences: each partial derivative is a bilinear blend of its 4 edges), and
/// - `box` and `boundaryMin`: a lower bound of phi on the box faces; a node whose centre is outside the box
///   while a point under it is inside could only touch if boundaryMin - lipschitz * rho <= sigma.
/// The node test becomes: the centre's segment reaches sigma + lipschitz * rho inside the box, or it passes
/// within rho of the box from outside and boundaryMin - lipschitz * rho <= sigma. With that, the tree
/// returns exactly the contacts of the point-by-point query (tests pin it on random grids).
///
/// A field that is not continuous (TriangleSetField: a point just behind a triangle is inside, one just past the
/// slab's back face or beside the open edge is outside again) reports how far phi can drop across a jump
/// (`jump`); every culling bound subtracts it.
///
/// Analytic fields are 1-Lipschitz and unbounded: the default bounds (the paper's assumption). A GridField
/// computes its bounds once, on first use (O(cells)), and holds them (GridField::cullingBounds());
/// fieldCullingBounds() (field_interface.h) answers for any field type.
#pragma once

#include "sdfccd/field/sdf_grid.h"
#include "sdfccd/math_types.h"

namespace sdfccd {

/// The bounds the point tree's culling relies on (see the file comment).
struct FieldCullingBounds {
  double lipschitz = 1.0;    ///< bound on |grad phi| wherever the segment query sees the field
  bool bounded = false;      ///< true: no contact outside `box`
  Box3 box;                  ///< the field's box, field frame (bounded only)
  double boundaryMin = 0.0;  ///< lower bound of phi on the box faces (model units; bounded only)
  /// Largest drop of phi across its discontinuities (model units): phi(q) >= phi(p) - lipschitz |p - q| - jump
  /// for any p, q. 0 for a continuous field; a TriangleSetField's slabs give 2 x thickness. The culling grows
  /// sigma by it where the field cannot rule it out (fieldJumpNear, field_interface.h).
  double jump = 0.0;
};

/// The bounds of a grid, computed in one pass over its cells (GridField::cullingBounds() holds them).
FieldCullingBounds computeCullingBounds(const SdfGrid& grid);

}  // namespace sdfccd
