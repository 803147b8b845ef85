/// @file
/// @brief PenetrationProbe (see penetration_probe.h).
#if __has_include("sdfccd/bullet/scene_world.h")  // built only with the Bullet plugin
#include "bench/penetration_probe.h"

#include <algorithm>
#include <limits>

#include "sdfccd/error.h"

namespace sdfccd::cli {

PenetrationProbe::PenetrationProbe(std::vector<std::shared_ptr<const BodyModel>> models, std::vector<bool> isStatic,
                                   std::optional<double> groundHeight)
    : m_models(std::move(models)), m_isStatic(std::move(isStatic)), m_groundHeight(groundHeight) {
  if (m_isStatic.size() != m_models.size()) throw Error("PenetrationProbe: one static flag per model is needed");
  for (const auto& model : m_models) {
    double radius = 0.0;
    for (const Vec3& v : model->meshInBody().vertices) radius = std::max(radius, v.norm());
    m_radius.push_back(radius);
    m_cellSize = std::max(m_cellSize, model->cellSize());
  }
}

std::vector<double> PenetrationProbe::clearance(const std::vector<Rigid>& worldFromBody) const {
  std::vector<double> out;
  if (!m_groundHeight) return out;
  for (std::size_t a = 0; a < m_models.size(); ++a) {
    if (m_isStatic[a]) continue;
    // Only the vertical component matters: the lowest vertex is the lowest of (row y of R) . v.
    const Vec3 up = worldFromBody[a].linear().row(1).transpose();
    double lowest = std::numeric_limits<double>::infinity();
    for (const Vec3& v : m_models[a]->meshInBody().vertices) lowest = std::min(lowest, up.dot(v));
    out.push_back(worldFromBody[a].translation().y() + lowest - *m_groundHeight);
  }
  return out;
}

PenetrationSample PenetrationProbe::measure(const std::vector<Rigid>& worldFromBody) const {
  PenetrationSample sample;
  for (double c : clearance(worldFromBody)) sample.groundMetres = std::max(sample.groundMetres, -c);
  const std::size_t n = m_models.size();
  for (std::size_t a = 0; a < n; ++a) {
    for (std::size_t b = 0; b < n; ++b) {
      if (a == b || (m_isStatic[a] && m_isStatic[b])) continue;
      const double reach = m_radius[a] + m_radius[b];
      if ((worldFromBody[a].translation() - worldFromBody[b].translation()).squaredNorm() > reach * reach) continue;
      const BodyModel& field = *m_models[b];
      const Rigid fieldFromBodyA =
          (worldFromBody[b] * field.bodyFromField()).inverse(Eigen::Isometry) * worldFromBody[a];
      for (const Vec3& v : m_models[a]->meshInBody().vertices) {
        const Vec3 p = fieldFromBodyA * v;
        if (!field.field().contains(p)) continue;
        sample.bodyMetres = std::max(sample.bodyMetres, -field.field().distance(p));
      }
    }
  }
  return sample;
}

std::vector<int> PenetrationProbe::tunneled(const std::vector<Rigid>& worldFromBody) const {
  std::vector<int> out;
  for (std::size_t a = 0; a < m_models.size(); ++a) {
    if (m_isStatic[a]) continue;
    const Vec3 com = worldFromBody[a].translation();
    bool through = m_groundHeight && com.y() < *m_groundHeight;
    for (std::size_t b = 0; b < m_models.size() && !through; ++b) {
      if (a == b) continue;
      const BodyModel& field = *m_models[b];
      const Vec3 p = (worldFromBody[b] * field.bodyFromField()).inverse(Eigen::Isometry) * com;
      through = field.field().contains(p) && field.field().distance(p) < 0.0;
    }
    if (through) out.push_back(static_cast<int>(a));
  }
  return out;
}

}  // namespace sdfccd::cli

#endif
