/// @file
/// @brief The field interface, written down once: what every distance field type of sdfccd provides, and the
/// free functions built on it (paper Sections 3.1-3.3).
///
/// @details Five field types exist: GridField (grid_field.h, a sampled SDF with its octree) and the analytic
/// PlaneField, SphereField, BoxField and CapsuleField (analytic_fields.h). They share no base class: the
/// segment walk, the point tree, the penalty model and the haptic renderers take the field type as a template
/// parameter (OpenVDB's search policy, not a virtual call per cell), and the library instantiates them
/// explicitly for these five (SDFCCD_FOR_EACH_FIELD). Every field type provides, all in the field's frame
/// ("Sdf": positions `pointInSdf`, model units), immutable and safe to query from many threads:
///
///   bool contains(const Vec3& pointInSdf) const;   // inside the region where the field is defined
///                                                  // (the grid's box; analytic fields: everywhere)
///   double distance(const Vec3& pointInSdf) const; // phi, negative inside; defined everywhere (a grid
///                                                  // field grows outside its box, never in contact there)
///   Vec3 gradient(const Vec3& pointInSdf) const;   // grad phi (a grid's is not normalized; zero where
///                                                  // an analytic field has no direction)
///   void intersectSegment(const Vec3& p0InSdf, const Vec3& p1InSdf, const SegmentCcdSettings& settings,
///                         SegmentCcdResult& outResult) const;  // the segment query, policy in segment_ccd.h
///
/// A GridField also holds its culling bounds (cullingBounds(), field_culling_bounds.h); fieldCullingBounds()
/// below answers for any field type.
#pragma once

#include <type_traits>
#include <utility>

#include "sdfccd/ccd/segment_ccd.h"
#include "sdfccd/field/field_culling_bounds.h"
#include "sdfccd/math_types.h"

namespace sdfccd {

class GridField;
class PlaneField;
class SphereField;
class BoxField;
class CapsuleField;

/// Expands X(Field) for every field type of the library: the explicit instantiations of the templates over
/// the field (rigid CCD, contact query, penalty model, haptic renderers) use it.
#define SDFCCD_FOR_EACH_FIELD(X) X(GridField) X(PlaneField) X(SphereField) X(BoxField) X(CapsuleField)

/// The segment query returning its result by value (allocates when there are more than IntervalList::kInline
/// intervals; a hot loop reuses one result with the member function instead).
template <class Field>
SegmentCcdResult intersectSegment(const Field& field, const Vec3& p0InSdf, const Vec3& p1InSdf,
                                  const SegmentCcdSettings& settings) {
  SegmentCcdResult result;
  field.intersectSegment(p0InSdf, p1InSdf, settings, result);
  return result;
}

namespace detail {
template <class Field, class = void>
struct HasCullingBounds : std::false_type {};
template <class Field>
struct HasCullingBounds<Field, std::void_t<decltype(std::declval<const Field&>().cullingBounds())>> : std::true_type {};
}  // namespace detail

namespace detail {
template <class Field, class = void>
struct HasJumpReachable : std::false_type {};
template <class Field>
struct HasJumpReachable<Field, std::void_t<decltype(std::declval<const Field&>().jumpReachable(
                                   std::declval<const Vec3&>(), std::declval<const Vec3&>(), 0.0))>> : std::true_type {
};
}  // namespace detail

/// The drop the culling must allow for points within `reach` of the segment [c0, c1] beyond `bounds.lipschitz`
/// (field_culling_bounds.h): 0 for a continuous field, else `bounds.jump` unless the field can tell that no
/// jump is within reach (TriangleSetField::jumpReachable).
template <class Field>
double fieldJumpNear(const Field& field, const FieldCullingBounds& bounds, const Vec3& c0, const Vec3& c1,
                     double reach) {
  if (!(bounds.jump > 0.0)) return 0.0;
  if constexpr (detail::HasJumpReachable<Field>::value) {
    return field.jumpReachable(c0, c1, reach) ? bounds.jump : 0.0;
  } else {
    return bounds.jump;
  }
}

/// What the point tree's culling may assume of `field` (field_culling_bounds.h): a grid field's own bounds;
/// for the analytic fields (exact distances, 1-Lipschitz, defined everywhere) the paper's assumption.
template <class Field>
FieldCullingBounds fieldCullingBounds(const Field& field) {
  if constexpr (detail::HasCullingBounds<Field>::value) {
    return field.cullingBounds();
  } else {
    (void)field;
    return {};
  }
}

}  // namespace sdfccd
