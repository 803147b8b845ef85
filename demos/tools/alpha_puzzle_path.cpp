/// @file
/// @brief alpha_puzzle_path: plans the motion that takes the procedural alpha puzzle apart (paper Section 5, the
/// alpha puzzle) and prints it as the keyframes of a haptic scene's user script.
///
/// @details The pieces are the generator's (alpha_puzzle_piece.h): tubes of radius r along the alpha curve, the
/// moving piece starting at alphaPuzzleInterlockedPose(). Two tubes are apart by clearance = (distance between
/// their centre polylines) - 2 r: exact for capsule chains, and a lower bound for the meshes (their polygonal
/// rings lie inside the circle). The planner is RRT-Connect (Kuffner and LaValle 2000) in the moving piece's
/// pose, rotation about its centroid: one tree grows from the interlocked pose, one from a pose far away; every
/// state and every edge (sampled so that no curve point moves more than `edgeStep` between samples) keeps the
/// clearance above `margin`. The found path is shortened by random shortcuts, then printed as JSON keyframes in
/// the scene's units (`poseFrame: "mesh"`: the pose of the mesh's own frame, scaled by `scale`), timed at
/// `speed` (model units of the fastest curve point per second). Deterministic for a given seed.
///
/// The generator's pieces cannot be separated as they are: where a loop crosses itself its strands' centre curves
/// come 0.597 apart, their surfaces 0.297, less than the other tube's diameter (0.3). `thinning` makes the fixed
/// piece's tube thinner (the scene offsets its field by as much); with 0.01 (6.7% of the radius) a path with
/// clearance 0.003 exists and RRT-Connect finds it in about a million clearance evaluations.
///
/// Usage: alpha_puzzle_path [margin=0.003] [thinning=0.01] [scale=0.02] [speed=1.5] [seed=1] [maxNodes=80000]
/// (margin, thinning in generator units; speed in generator units per second). Prints the keyframes to stdout and
/// the planner's statistics to stderr; scripts/make_alpha_puzzle_solved.py turns them into the scene files.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "sdfccd/mesh/mass_properties.h"
#include "sdfccd/model/alpha_puzzle_piece.h"

namespace {

using sdfccd::Quat;
using sdfccd::Rigid;
using sdfccd::Vec3;

/// A chain of capsules (a tube's centre polyline) cut into chunks with bounding spheres for culling.
struct CapsuleChain {
  std::vector<Vec3> points;
  struct Chunk {
    int first, last;  ///< segment range [first, last)
    Vec3 centre;
    double radius;
  };
  std::vector<Chunk> chunks;
};

CapsuleChain makeChain(std::vector<Vec3> points, int chunkSegments) {
  CapsuleChain chain;
  chain.points = std::move(points);
  const int segments = static_cast<int>(chain.points.size()) - 1;
  for (int first = 0; first < segments; first += chunkSegments) {
    const int last = std::min(segments, first + chunkSegments);
    Vec3 centre = Vec3::Zero();
    for (int i = first; i <= last; ++i) centre += chain.points[i];
    centre /= double(last - first + 1);
    double radius = 0.0;
    for (int i = first; i <= last; ++i) radius = std::max(radius, (chain.points[i] - centre).norm());
    chain.chunks.push_back({first, last, centre, radius});
  }
  return chain;
}

/// Distance between segments [p0, p1] and [q0, q1] (closest points by clamped parameters, Ericson 5.1.9).
double segmentDistance(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1) {
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  const double c = d1.dot(r), b = d1.dot(d2), denom = a * e - b * b;
  double s = denom > 1e-14 * a * e ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
  double t = (b * s + f) / e;
  if (t < 0.0) {
    t = 0.0;
    s = std::clamp(-c / a, 0.0, 1.0);
  } else if (t > 1.0) {
    t = 1.0;
    s = std::clamp((b - c) / a, 0.0, 1.0);
  }
  return ((p0 + s * d1) - (q0 + t * d2)).norm();
}

/// The moving piece's pose: rotation `rotation` about its start centroid, then translation `shift`.
struct State {
  Vec3 shift = Vec3::Zero();
  Quat rotation = Quat::Identity();
};

/// The two pieces and the clearance between them.
class AlphaPair {
 public:
  /// `thinning`: the fixed piece's tube radius made smaller by this (model units), as a field offset does.
  explicit AlphaPair(double thinning) {
    sdfccd::AlphaPuzzlePieceSettings settings;
    settings.samples = 200;  // chord sagitta under 0.001 at the curve's tightest bend (radius 0.248)
    m_radii = 2.0 * settings.radius - thinning;
    const std::vector<Vec3> curve = sdfccd::alphaPuzzleCurve(settings);
    m_fixed = makeChain(curve, 8);
    const Rigid interlocked = sdfccd::alphaPuzzleInterlockedPose();
    m_movingStart = curve;
    for (Vec3& p : m_movingStart) p = interlocked * p;
    // The pivot is the moving piece's centre of mass: the scene's script interpolates that point linearly.
    m_centreOfMass = sdfccd::computeMassProperties(sdfccd::makeAlphaPuzzlePiece(), {0.0, 1.0}).centerOfMassInMesh;
    m_pivot = interlocked * m_centreOfMass;
    m_moving = makeChain(m_movingStart, 8);
    m_reach = 0.0;
    for (const Vec3& p : m_movingStart) m_reach = std::max(m_reach, (p - m_pivot).norm());
  }
  /// Surface-to-surface clearance (model units; negative: the tubes overlap).
  double clearance(const State& s) const {
    std::vector<Vec3> moved(m_movingStart.size());
    for (std::size_t i = 0; i < moved.size(); ++i) moved[i] = place(s, m_movingStart[i]);
    double best = 1e300;
    for (const CapsuleChain::Chunk& cb : m_moving.chunks) {
      const Vec3 centre = place(s, cb.centre);
      for (const CapsuleChain::Chunk& ca : m_fixed.chunks) {
        if ((centre - ca.centre).norm() - ca.radius - cb.radius >= best) continue;
        for (int i = ca.first; i < ca.last; ++i)
          for (int j = cb.first; j < cb.last; ++j)
            best = std::min(best, segmentDistance(m_fixed.points[i], m_fixed.points[i + 1], moved[j], moved[j + 1]));
      }
    }
    return best - m_radii;
  }
  Vec3 place(const State& s, const Vec3& pointAtStart) const {
    return m_pivot + s.shift + s.rotation * (pointAtStart - m_pivot);
  }
  /// An upper bound of how far any curve point moves between two states.
  double travel(const State& a, const State& b) const {
    return (a.shift - b.shift).norm() + m_reach * a.rotation.angularDistance(b.rotation);
  }
  const Vec3& pivot() const { return m_pivot; }
  double reach() const { return m_reach; }
  /// The fixed piece's centre of mass (the pieces are identical: the moving piece's, in its own frame).
  const Vec3& fixedCentreOfMass() const { return m_centreOfMass; }

 private:
  CapsuleChain m_fixed, m_moving;
  std::vector<Vec3> m_movingStart;
  Vec3 m_pivot, m_centreOfMass;
  double m_radii = 0.0;  ///< sum of the two tubes' radii
  double m_reach = 0.0;
};

State interpolate(const State& a, const State& b, double u) {
  return {a.shift + u * (b.shift - a.shift), a.rotation.slerp(u, b.rotation)};
}

struct Planner {
  const AlphaPair& pair;
  double margin;           ///< smallest clearance allowed (model units)
  double edgeStep = 0.01;  ///< largest travel between two checked states of an edge
  double extendStep = 0.15;
  std::int64_t clearanceCalls = 0;

  bool free(const State& s) {
    ++clearanceCalls;
    return pair.clearance(s) >= margin;
  }
  bool edgeFree(const State& a, const State& b) {
    const int steps = std::max(1, int(std::ceil(pair.travel(a, b) / edgeStep)));
    for (int k = 1; k <= steps; ++k)
      if (!free(interpolate(a, b, double(k) / steps))) return false;
    return true;
  }
};

struct Tree {
  std::vector<State> states;
  std::vector<int> parent;
  int nearest(const AlphaPair& pair, const State& s) const {
    int best = 0;
    double bestD = 1e300;
    for (std::size_t i = 0; i < states.size(); ++i) {
      const double d = pair.travel(states[i], s);
      if (d < bestD) bestD = d, best = int(i);
    }
    return best;
  }
  std::vector<State> pathTo(int i) const {
    std::vector<State> path;
    for (; i >= 0; i = parent[i]) path.push_back(states[i]);
    return path;  // from i back to the root
  }
};

enum class Extend { Trapped, Advanced, Reached };

/// Grows `tree` one step towards `target`; the new node is the tree's last.
Extend extend(Planner& planner, Tree& tree, const State& target) {
  const int near = tree.nearest(planner.pair, target);
  const State& from = tree.states[near];
  const double d = planner.pair.travel(from, target);
  const bool reach = d <= planner.extendStep;
  const State to = reach ? target : interpolate(from, target, planner.extendStep / d);
  if (!planner.edgeFree(from, to)) return Extend::Trapped;
  tree.states.push_back(to);
  tree.parent.push_back(near);
  return reach ? Extend::Reached : Extend::Advanced;
}

State randomState(std::mt19937_64& rng, double box) {
  std::uniform_real_distribution<double> u(-box, box);
  std::normal_distribution<double> n(0.0, 1.0);
  Quat q(n(rng), n(rng), n(rng), n(rng));
  return {Vec3(u(rng), u(rng), u(rng)), q.normalized()};
}

/// RRT-Connect between start and goal; empty if not found within maxNodes.
std::vector<State> plan(Planner& planner, const State& start, const State& goal, int maxNodes, unsigned seed) {
  std::mt19937_64 rng(seed);
  Tree a{{start}, {-1}}, b{{goal}, {-1}};
  bool aIsStart = true;
  while (int(a.states.size() + b.states.size()) < maxNodes) {
    const State target = randomState(rng, 4.0);
    if (extend(planner, a, target) != Extend::Trapped) {
      const State reached = a.states.back();
      Extend e = Extend::Advanced;
      while (e == Extend::Advanced) e = extend(planner, b, reached);
      if (e == Extend::Reached) {
        std::vector<State> fromA = a.pathTo(int(a.states.size()) - 1);  // reached .. a's root
        std::vector<State> fromB = b.pathTo(int(b.states.size()) - 1);  // reached .. b's root
        std::reverse(fromA.begin(), fromA.end());
        fromA.insert(fromA.end(), fromB.begin() + 1, fromB.end());
        if (!aIsStart) std::reverse(fromA.begin(), fromA.end());
        return fromA;
      }
    }
    std::swap(a, b);
    aIsStart = !aIsStart;
  }
  return {};
}

/// Random shortcuts: replaces the stretch between two path points by a straight edge when it is free.
void shorten(Planner& planner, std::vector<State>& path, int tries, unsigned seed) {
  std::mt19937_64 rng(seed);
  for (int k = 0; k < tries && path.size() > 2; ++k) {
    std::uniform_int_distribution<std::size_t> pick(0, path.size() - 1);
    std::size_t i = pick(rng), j = pick(rng);
    if (i > j) std::swap(i, j);
    if (j < i + 2) continue;
    if (planner.edgeFree(path[i], path[j])) path.erase(path.begin() + long(i) + 1, path.begin() + long(j));
  }
}

/// Ends the path at its first state from which a straight pull, away from the fixed piece, is free and takes the
/// centres `separation` apart (the goal's orientation is arbitrary: this drops the turn back to it).
void pullAwayEarly(Planner& planner, std::vector<State>& path, double separation) {
  const AlphaPair& pair = planner.pair;
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const Vec3 away = pair.pivot() + path[i].shift - pair.fixedCentreOfMass();
    State out = path[i];
    out.shift += (separation - away.norm()) * away.normalized();
    if (away.norm() < separation && planner.edgeFree(path[i], out)) {
      path.resize(i + 1);
      path.push_back(out);
      return;
    }
  }
}

double argument(int argc, char** argv, int index, double fallback) {
  return argc > index ? std::strtod(argv[index], nullptr) : fallback;
}

}  // namespace

int main(int argc, char** argv) {
  const double margin = argument(argc, argv, 1, 0.003);
  const double thinning = argument(argc, argv, 2, 0.01);
  const double scale = argument(argc, argv, 3, 0.02);
  const double speed = argument(argc, argv, 4, 1.5);
  const unsigned seed = unsigned(argument(argc, argv, 5, 1));
  const int maxNodes = int(argument(argc, argv, 6, 80000));
  const AlphaPair pair(thinning);
  Planner planner{pair, margin};
  const State start;
  std::fprintf(stderr, "start clearance %.4f (margin %.3f)\n", pair.clearance(start), margin);
  // The goal: the moving piece out along the line from the fixed piece's centre of mass through its own, with the
  // centres 1.3 piece lengths apart (the piece is 4.9 units long in y).
  State goal;
  const Vec3 away = pair.pivot() - pair.fixedCentreOfMass();
  goal.shift = (1.3 * 4.9 - away.norm()) * away.normalized();
  if (!planner.free(start) || !planner.free(goal)) {
    std::fprintf(stderr, "start or goal closer than the margin\n");
    return 2;
  }
  std::vector<State> path = plan(planner, start, goal, maxNodes, seed);
  if (path.empty()) {
    std::fprintf(stderr, "no path within %d nodes (%lld clearance calls)\n", maxNodes,
                 static_cast<long long>(planner.clearanceCalls));
    return 1;
  }
  const std::size_t raw = path.size();
  shorten(planner, path, 3000, seed + 1);
  pullAwayEarly(planner, path, 1.3 * 4.9);
  // The smallest clearance along the final path, sampled finer than the planner did.
  double smallest = 1e300;
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const int steps = std::max(1, int(std::ceil(pair.travel(path[i], path[i + 1]) / 0.002)));
    for (int k = 0; k <= steps; ++k)
      smallest = std::min(smallest, pair.clearance(interpolate(path[i], path[i + 1], double(k) / steps)));
  }
  std::fprintf(stderr, "path: %zu states (%zu before shortening), smallest clearance %.4f, %lld clearance calls\n",
               path.size(), raw, smallest, static_cast<long long>(planner.clearanceCalls));
  // Keyframes: the pose of the moving mesh's frame = (this state) * interlocked pose, scaled.
  const Rigid interlocked = sdfccd::alphaPuzzleInterlockedPose();
  const Quat startRotation(interlocked.linear());
  double t = 0.5;  // half a second at rest first
  std::printf("[\n");
  for (std::size_t i = 0; i < path.size(); ++i) {
    if (i > 0) t += std::max(0.05, pair.travel(path[i - 1], path[i]) / speed);
    const State& s = path[i];
    const Vec3 position = scale * (pair.pivot() + s.shift + s.rotation * (interlocked.translation() - pair.pivot()));
    const Eigen::AngleAxisd aa((s.rotation * startRotation).normalized());
    const Vec3 rv = aa.angle() * aa.axis();
    const auto keyframe = [&](double time, const char* end) {
      std::printf("  {\"t\": %.3f, \"position\": [%.9f, %.9f, %.9f], \"rotationVector\": [%.9f, %.9f, %.9f]}%s\n", time,
                  position.x(), position.y(), position.z(), rv.x(), rv.y(), rv.z(), end);
    };
    if (i == 0) keyframe(0.0, ",");
    keyframe(t, ",");
    if (i + 1 == path.size()) keyframe(t + 0.5, "");  // half a second at rest at the end
  }
  std::printf("]\n");
  return 0;
}
