/// @file
/// @brief UserScript: keyframed / recorded target poses of the emulated user.
#include "sdfccd/haptics/user_script.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "sdfccd/error.h"
#include "sdfccd/haptics/rigid_body_state.h"
#include "sdfccd/tolerances.h"

namespace sdfccd::haptics {

UserScript::UserScript(std::vector<PoseKeyframe> keys) : m_keys(std::move(keys)) {
  if (m_keys.empty()) throw Error("user script: no keyframes");
  for (std::size_t i = 0; i < m_keys.size(); ++i) {
    const PoseKeyframe& k = m_keys[i];
    if (!std::isfinite(k.time) || !k.worldFromTarget.matrix().allFinite())
      throw Error("user script: keyframe " + std::to_string(i) + " is not finite");
    if (i > 0 && !(k.time > m_keys[i - 1].time))
      throw Error("user script: keyframe times must increase (keyframe " + std::to_string(i) + ")");
  }
}

UserScript UserScript::loadCsv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error("cannot open trajectory '" + path + "'");
  std::string line;
  if (!std::getline(in, line)) throw Error(path + ": empty file");
  line.erase(std::remove_if(line.begin(), line.end(), [](char c) { return c == ' ' || c == '\r'; }), line.end());
  if (line != "t,x,y,z,qw,qx,qy,qz") throw Error(path + ":1: expected the header t,x,y,z,qw,qx,qy,qz");
  std::vector<PoseKeyframe> keys;
  int lineNo = 1;
  while (std::getline(in, line)) {
    ++lineNo;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    std::stringstream ss(line);
    std::string cell;
    double v[8];
    int n = 0;
    while (std::getline(ss, cell, ',')) {
      if (n >= 8) throw Error(path + ":" + std::to_string(lineNo) + ": more than 8 columns");
      char* end = nullptr;
      v[n] = std::strtod(cell.c_str(), &end);
      if (end == cell.c_str() || *end != '\0') {
        // allow trailing blanks
        while (end && (*end == ' ' || *end == '\t')) ++end;
        if (end == cell.c_str() || (end && *end != '\0'))
          throw Error(path + ":" + std::to_string(lineNo) + ": '" + cell + "' is not a number");
      }
      if (!std::isfinite(v[n])) throw Error(path + ":" + std::to_string(lineNo) + ": non-finite value");
      ++n;
    }
    if (n != 8) throw Error(path + ":" + std::to_string(lineNo) + ": expected 8 columns, got " + std::to_string(n));
    Quat q(v[4], v[5], v[6], v[7]);
    if (!(q.norm() > tolerance::kMinDirectionLength))
      throw Error(path + ":" + std::to_string(lineNo) + ": zero quaternion");
    q.normalize();
    PoseKeyframe k;
    k.time = v[0];
    k.worldFromTarget.linear() = q.toRotationMatrix();
    k.worldFromTarget.translation() = Vec3(v[1], v[2], v[3]);
    if (!keys.empty() && !(k.time > keys.back().time))
      throw Error(path + ":" + std::to_string(lineNo) + ": times must increase");
    keys.push_back(k);
  }
  if (keys.empty()) throw Error(path + ": no trajectory rows");
  return UserScript(std::move(keys));
}

Rigid UserScript::targetAt(double time) const {
  if (m_keys.empty()) return Rigid::Identity();
  if (!(time > m_keys.front().time)) return m_keys.front().worldFromTarget;
  if (time >= m_keys.back().time) return m_keys.back().worldFromTarget;
  const auto it =
      std::upper_bound(m_keys.begin(), m_keys.end(), time, [](double t, const PoseKeyframe& k) { return t < k.time; });
  const PoseKeyframe& b = *it;
  const PoseKeyframe& a = *(it - 1);
  return interpolatePose(a.worldFromTarget, b.worldFromTarget, (time - a.time) / (b.time - a.time));
}

double UserScript::peakSpeed() const {
  double peak = 0.0;
  for (std::size_t i = 1; i < m_keys.size(); ++i) {
    const double dt = m_keys[i].time - m_keys[i - 1].time;
    const double d = (m_keys[i].worldFromTarget.translation() - m_keys[i - 1].worldFromTarget.translation()).norm();
    if (dt > 0.0) peak = std::max(peak, d / dt);
  }
  return peak;
}

}  // namespace sdfccd::haptics
