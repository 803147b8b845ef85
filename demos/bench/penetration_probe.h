/// @file
/// @brief PenetrationProbe: how deep bodies are in the ground and in each other, measured from their poses
/// alone, so that two worlds (our plugin and the GImpact peer of `sdfccd bench bullet --part peer`) are
/// measured the same way.
///
/// @details Ground: the deepest mesh vertex below the ground plane. Body vs body: every mesh vertex of one
/// body looked up in the distance field of the other (its BodyModel's grid, trilinear), both orders,
/// for the pairs whose bounding spheres overlap; the deepest -phi. Both in metres and in cells of the fields
/// (the largest cell of the scene's models). The mesh vertices are what GImpact collides; our plugin collides
/// its point shell, so this measure does not favour it. Tunnelled: a dynamic body whose centre of mass is
/// below the ground or inside another body (phi < 0 there).
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "sdfccd/math_types.h"
#include "sdfccd/model/body_model.h"

namespace sdfccd::cli {

/// One measurement (the deepest over all bodies).
struct PenetrationSample {
  double groundMetres = 0.0;  ///< deepest vertex below the ground (m, >= 0)
  double bodyMetres = 0.0;    ///< deepest vertex inside another body (m, >= 0)
};

class PenetrationProbe {
 public:
  /// `models[i]` and `isStatic[i]` describe body i; no ground when groundHeight is empty.
  PenetrationProbe(std::vector<std::shared_ptr<const BodyModel>> models, std::vector<bool> isStatic,
                   std::optional<double> groundHeight);

  PenetrationSample measure(const std::vector<Rigid>& worldFromBody) const;
  /// Per dynamic body, the height of its lowest mesh vertex above the ground (m; negative: below). Shows where
  /// bodies rest: a contact margin keeps them above it. Empty without a ground.
  std::vector<double> clearance(const std::vector<Rigid>& worldFromBody) const;
  /// The dynamic bodies that tunnelled (see the file comment).
  std::vector<int> tunneled(const std::vector<Rigid>& worldFromBody) const;
  /// The largest field cell of the models (m): divide by it for cells.
  double cellSize() const { return m_cellSize; }

 private:
  std::vector<std::shared_ptr<const BodyModel>> m_models;
  std::vector<bool> m_isStatic;
  std::optional<double> m_groundHeight;
  std::vector<double> m_radius;  // bounding sphere of each mesh about its centre of mass (m)
  double m_cellSize = 0.0;
};

}  // namespace sdfccd::cli
