/// @file
/// @brief JsonReader: strict typed reads with one-line errors, and scene file lookup (detail/json_reader.h).
#include "sdfccd/model/detail/json_reader.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "sdfccd/error.h"

namespace sdfccd::detail {

std::optional<std::string> findSceneFile(const std::string& given, const SceneFileSearch& search) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::path(given).is_absolute()) {
    if (fs::is_regular_file(given, ec)) return given;
    return std::nullopt;
  }
  if (fs::is_regular_file(given, ec)) return given;
  fs::path dir = fs::path(search.sceneFolder.empty() ? "." : search.sceneFolder);
  for (int up = 0; up < 4; ++up) {
    const fs::path candidate = dir / given;
    if (fs::is_regular_file(candidate, ec)) return candidate.lexically_normal().string();
    if (!dir.has_parent_path() || dir.parent_path() == dir) break;
    dir = dir.parent_path();
  }
  for (const std::string& folder : search.extraFolders) {
    const fs::path candidate = fs::path(folder) / given;
    if (fs::is_regular_file(candidate, ec)) return candidate.lexically_normal().string();
  }
  return std::nullopt;
}

std::string readSceneText(const std::string& path) {
  // Scene files are a few kB; the limit keeps /dev/zero or a mistaken multi-GB file from filling memory.
  constexpr std::size_t kMaxSceneBytes = 16u << 20;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("scene '" + path + "': cannot be read");
  std::string text;
  char chunk[65536];
  while (in.read(chunk, sizeof chunk) || in.gcount() > 0) {
    text.append(chunk, static_cast<std::size_t>(in.gcount()));
    if (text.size() > kMaxSceneBytes) throw Error("scene '" + path + "': larger than 16 MiB (not a scene file)");
  }
  if (in.bad()) throw Error("scene '" + path + "': cannot be read");
  return text;
}

void JsonReader::fail(const std::string& where, const std::string& what) const {
  throw Error("scene '" + m_scene + "': " + where + (where.empty() ? "" : " ") + what);
}

std::string JsonReader::numberText(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

std::string JsonReader::join(const std::string& where, const std::string& key) {
  return where.empty() ? key : where + "." + key;
}

Json JsonReader::parseObject(const std::string& text) const {
  Json root;
  try {
    root = Json::parse(text);
  } catch (const Json::exception& e) {  // parse errors, and number overflow (1e999) as out_of_range
    const std::string what = e.what();
    fail("", "is not valid JSON (" + what.substr(0, what.find('\n')) + ")");
  }
  checkObject(root, "");
  return root;
}

void JsonReader::checkObject(const Json& j, const std::string& where) const {
  if (!j.is_object()) fail(where.empty() ? "the top level" : where, "must be a JSON object");
}

void JsonReader::checkKeys(const Json& j, const std::set<std::string>& allowed, const std::string& where) const {
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (allowed.count(it.key()) == 0) {
      std::string list;
      for (const std::string& k : allowed) list += (list.empty() ? "" : ", ") + k;
      fail(join(where, it.key()), "is not a known key (known: " + list + ")");
    }
  }
}

const Json& JsonReader::object(const Json& j, const std::string& key, const std::string& where) const {
  if (!j.contains(key)) fail(join(where, key), "is missing");
  const Json& v = j.at(key);
  checkObject(v, join(where, key));
  return v;
}

double JsonReader::number(const Json& j, const std::string& key, const std::string& where, double fallback,
                          bool required) const {
  if (!j.contains(key)) {
    if (required) fail(join(where, key), "is missing");
    return fallback;
  }
  const Json& v = j.at(key);
  if (!v.is_number()) fail(join(where, key), "must be a number");
  const double d = v.get<double>();
  if (!std::isfinite(d)) fail(join(where, key), "must be finite");
  return d;
}

double JsonReader::positive(const Json& j, const std::string& key, const std::string& where, double fallback,
                            bool required) const {
  const double v = number(j, key, where, fallback, required);
  if (!(v > 0.0)) fail(join(where, key), "must be > 0 (got " + numberText(v) + ")");
  return v;
}

double JsonReader::nonNegative(const Json& j, const std::string& key, const std::string& where, double fallback,
                               bool required) const {
  const double v = number(j, key, where, fallback, required);
  if (!(v >= 0.0)) fail(join(where, key), "must be >= 0 (got " + numberText(v) + ")");
  return v;
}

double JsonReader::ranged(const Json& j, const std::string& key, const std::string& where, double fallback, double lo,
                          double hi, bool lowOpen) const {
  if (!j.contains(key)) return fallback;
  const double v = number(j, key, where, fallback);
  const bool above = lowOpen ? v > lo : v >= lo;
  if (!above || !(v <= hi)) {
    fail(join(where, key), "must be in " + std::string(lowOpen ? "(" : "[") + numberText(lo) + ", " + numberText(hi) +
                               "] (got " + numberText(v) + ")");
  }
  return v;
}

Vec3 JsonReader::boundedVec3(const Json& j, const std::string& key, const std::string& where, const Vec3& fallback,
                             double bound) const {
  const Vec3 v = vec3(j, key, where, fallback);
  if (!(v.cwiseAbs().maxCoeff() <= bound)) {
    fail(join(where, key), "must have components in [-" + numberText(bound) + ", " + numberText(bound) + "] (got " +
                               numberText(v.cwiseAbs().maxCoeff()) + ")");
  }
  return v;
}

int JsonReader::integer(const Json& j, const std::string& key, const std::string& where, int fallback, int lo,
                        int hi) const {
  if (!j.contains(key)) return fallback;
  const Json& v = j.at(key);
  if (!v.is_number_integer()) fail(join(where, key), "must be an integer");
  const std::string range = "must be in " + std::to_string(lo) + ".." + std::to_string(hi);
  // Integers past INT64_MAX arrive as unsigned: compared as unsigned, never converted to a negative.
  if (v.is_number_unsigned() && v.get<unsigned long long>() > static_cast<unsigned long long>(hi)) {
    fail(join(where, key), range + " (got " + std::to_string(v.get<unsigned long long>()) + ")");
  }
  const long long n = v.get<long long>();
  if (n < lo || n > hi) {
    fail(join(where, key),
         "must be in " + std::to_string(lo) + ".." + std::to_string(hi) + " (got " + std::to_string(n) + ")");
  }
  return static_cast<int>(n);
}

bool JsonReader::boolean(const Json& j, const std::string& key, const std::string& where, bool fallback) const {
  if (!j.contains(key)) return fallback;
  if (!j.at(key).is_boolean()) fail(join(where, key), "must be true or false");
  return j.at(key).get<bool>();
}

std::string JsonReader::string(const Json& j, const std::string& key, const std::string& where) const {
  if (!j.contains(key)) return {};
  if (!j.at(key).is_string()) fail(join(where, key), "must be a string");
  return j.at(key).get<std::string>();
}

std::vector<double> JsonReader::numbers(const Json& j, const std::string& key, const std::string& where,
                                        std::size_t count) const {
  if (!j.contains(key)) fail(join(where, key), "is missing");
  const Json& v = j.at(key);
  if (!v.is_array() || v.size() != count)
    fail(join(where, key), "must be an array of " + std::to_string(count) + " numbers");
  std::vector<double> out;
  for (const Json& e : v) {
    if (!e.is_number()) fail(join(where, key), "must be an array of " + std::to_string(count) + " numbers");
    const double d = e.get<double>();
    if (!std::isfinite(d)) fail(join(where, key), "must hold finite numbers");
    out.push_back(d);
  }
  return out;
}

Vec3 JsonReader::vec3(const Json& j, const std::string& key, const std::string& where, const Vec3& fallback,
                      bool required) const {
  if (!j.contains(key)) {
    if (required) fail(join(where, key), "is missing");
    return fallback;
  }
  const std::vector<double> v = numbers(j, key, where, 3);
  return Vec3(v[0], v[1], v[2]);
}

Quat JsonReader::unitQuaternion(const Json& j, const std::string& key, const std::string& where) const {
  const std::vector<double> q = numbers(j, key, where, 4);
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (std::abs(norm - 1.0) > 1e-6) {
    fail(join(where, key), "must be a unit quaternion w, x, y, z (norm " + numberText(norm) + ")");
  }
  return Quat(q[0], q[1], q[2], q[3]).normalized();
}

std::string JsonReader::file(const Json& j, const std::string& key, const std::string& where) const {
  const std::string given = string(j, key, where);
  if (given.empty()) return {};
  if (const std::optional<std::string> found = findSceneFile(given, m_search)) return *found;
  if (!m_search.requireFiles) return given;
  fail(join(where, key), "names a missing file '" + given + "'");
}

}  // namespace sdfccd::detail
