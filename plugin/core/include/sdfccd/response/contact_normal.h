/// @file
/// @brief Which surface gives a contact's normal where a shell point of one body meets the field of another.
///
/// @details A pair of two shelled bodies runs two roles: A's points against B's field and B's points against A's
/// field. Each role alone would take its normal from one field's gradient. Where a flat face of one body meets
/// an edge or a corner of the other, the role whose field has the edge sees the gradient turn radial about it
/// (up to 45 degrees off the face for a box edge, more where the grid's interpolation rounds it) at points that
/// lie on the other body's flat face: a box sliding over a table would be pushed back and up by the table's own
/// face points passing under its bottom edge. The true normal of a face-on-edge contact is the face's.
///
/// The rule: the contact normal comes from the flatter of the two surfaces at the contact. Each surface's
/// curvature there is measured the same way, as the angle its normal turns per unit length:
/// - the field's, from its gradient at the point and at points one step away along two tangent directions
///   (fieldCurvature: zero on a face, about (pi/4) / step beside an edge, 1/R on a sphere of radius R);
/// - the shell's, from the point's outward normal and those of its neighbours on the shell (shellCurvatures,
///   point_shell.h:
///   zero inside a face, large at an edge's or a corner's averaged normals).
/// The shell's own normal (turned to point out of the field body) gets the weight
///   w = f max(0, k_field - k_shell - k_floor) / (k_field + k_floor),
/// where f is 1 when the turned normal lies within 60 degrees of the field's gradient and fades to 0 by 75: the
/// face of a box resting on another box's edge faces that edge, the side face of a box standing on another's top
/// face, flush with its side, does not (its normal there would push the stack sideways),
/// and the contact normal is normalize((1 - w) g - w m) for the field's unit gradient g and the shell's unit
/// normal m. A face on an edge takes the face's normal from whichever role sees it (w near 1 where the field has
/// the edge, 0 where the shell has it). Where neither surface is clearly the flatter (two faces, two edges, two
/// curved surfaces) the gradient stays exactly (w = 0), as it does on the ground: only a decided difference
/// moves a normal, so aligned stacks, whose edges meet edges, keep the rows that hold them. k_floor
/// (kCurvatureFloorPerStep / step) keeps a flat surface's noise from deciding anything.
#pragma once

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "sdfccd/field/analytic_fields.h"
#include "sdfccd/math_types.h"

namespace sdfccd {

/// Below this turn per step (rad) a surface counts as flat.
inline constexpr double kCurvatureFloorPerStep = 0.02;

/// The curvature of `field`'s level set through `pointInSdf` (rad per model unit): the largest angle its
/// gradient turns between the point and the four points `step` away along two tangent directions, over `step`.
/// `unitGradient`: the field's unit gradient at the point. A plane is flat everywhere (0, no lookup).
template <class Field>
double fieldCurvature(const Field& field, const Vec3& pointInSdf, const Vec3& unitGradient, double step) {
  if constexpr (std::is_same_v<Field, PlaneField>) {
    return 0.0;
  } else {
    if (!(step > 0.0)) return 0.0;
    const Vec3 t1 = unitGradient.unitOrthogonal();
    const Vec3 t2 = unitGradient.cross(t1);
    double largest = 0.0;
    for (const Vec3& offset : {Vec3(step * t1), Vec3(-step * t1), Vec3(step * t2), Vec3(-step * t2)}) {
      const Vec3 g = field.gradient(pointInSdf + offset);
      const double length = g.norm();
      if (!(length > 0.0) || !g.allFinite()) continue;
      largest = std::max(largest, angleBetween(unitGradient, g / length));
    }
    return largest / step;
  }
}

/// cos 75 and cos 60 degrees: the shell's normal (turned) takes over only where it is within 60 degrees of the
/// field's gradient (fully), fading out by 75 (a face beside an edge that it does not face keeps the gradient).
inline constexpr double kFacingCosineLow = 0.25881904510252074;
inline constexpr double kFacingCosineHigh = 0.5;

/// The weight of the shell's own normal in the contact normal (see the file comment), in [0, 1], from both
/// surfaces' curvatures (rad per model unit) measured over `step` (the field's cell), and from how far the turned
/// shell normal -m lies from the field's unit gradient g: `facing` = g . (-m).
inline double shellNormalWeight(double fieldCurvatureValue, double shellCurvatureValue, double facing, double step) {
  if (!(fieldCurvatureValue > 0.0) || !(step > 0.0)) return 0.0;
  const double floor = kCurvatureFloorPerStep / step;
  const double excess = fieldCurvatureValue - std::max(0.0, shellCurvatureValue) - floor;
  if (!(excess > 0.0)) return 0.0;
  const double faces = std::clamp((facing - kFacingCosineLow) / (kFacingCosineHigh - kFacingCosineLow), 0.0, 1.0);
  return faces * std::min(1.0, excess / (fieldCurvatureValue + floor));
}

/// The weight of the shell's normal for a contact at `pointInSdf` (field frame): `unitGradient`, the field's unit
/// gradient there; `unitShellNormalInSdf`, the shell point's outward normal turned into the field's frame;
/// `shellCurvatureValue`, the shell's curvature at the point; `step`, the field's cell.
template <class Field>
double shellNormalWeightAt(const Field& field, const Vec3& pointInSdf, const Vec3& unitGradient,
                           const Vec3& unitShellNormalInSdf, double shellCurvatureValue, double step) {
  const double facing = -unitGradient.dot(unitShellNormalInSdf);
  if (!(facing > kFacingCosineLow)) return 0.0;
  return shellNormalWeight(fieldCurvature(field, pointInSdf, unitGradient, step), shellCurvatureValue, facing, step);
}

/// normalize((1 - w) g - w m) for unit vectors g (the field's gradient) and m (the shell's outward normal); g when
/// w is 0 or the two cancel.
inline Vec3 arbitratedNormal(const Vec3& unitGradient, const Vec3& unitShellNormal, double w) {
  if (!(w > 0.0)) return unitGradient;
  const Vec3 mixed = (1.0 - w) * unitGradient - w * unitShellNormal;
  const double length = mixed.norm();
  if (!(length > 1e-6)) return unitGradient;
  return mixed / length;
}

}  // namespace sdfccd
