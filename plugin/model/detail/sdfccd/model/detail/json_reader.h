/// @file
/// @brief JsonReader: the strict-JSON helpers behind every scene file reader (simulation scenes, scene.h; haptic
/// scenes, sdfccd/haptics/haptic_scene.h): typed values, known keys, vectors and unit quaternions, and the files a
/// scene names, each defect a one-line sdfccd::Error naming the file and the key path.
///
/// @details Internal to the build: it exposes nlohmann::json, which sdfccd's installed targets do not require
/// (CMake target sdfccd_model_json, linked privately by the model layer and haptics; never installed).
///
/// Errors read "scene '<file>': <key path> <what>", e.g. "scene 'a.json': bodies[2].mass must be > 0 (got -1)".
/// Key paths join object keys with '.', and callers name array entries ("bodies[2]").
///
/// Files: an absolute path must exist; a relative one is tried against the current folder, then the scene's
/// folder and up to three of its ancestors (so "assets/meshes/bunny.off" works from assets/scenes/), then the extra
/// search folders in order.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "sdfccd/math_types.h"

namespace sdfccd::detail {

using Json = nlohmann::json;

/// Where the files a scene names are looked for.
struct SceneFileSearch {
  std::string sceneFolder;                ///< the scene file's folder ("" = the current folder)
  std::vector<std::string> extraFolders;  ///< tried last, in order
  bool requireFiles = true;               ///< false: a file found nowhere keeps the path as written
};

/// The path under which `given` exists (see the file comment), or nothing.
std::optional<std::string> findSceneFile(const std::string& given, const SceneFileSearch& search);

/// The whole content of a scene file. Throws sdfccd::Error "scene '<path>': cannot be read".
std::string readSceneText(const std::string& path);

class JsonReader {
 public:
  JsonReader(std::string sceneName, SceneFileSearch search = {})
      : m_scene(std::move(sceneName)), m_search(std::move(search)) {}

  const std::string& sceneName() const { return m_scene; }
  [[noreturn]] void fail(const std::string& where, const std::string& what) const;
  /// "where.key", or "key" at the top level.
  static std::string join(const std::string& where, const std::string& key);
  /// A number as errors quote it ("(got -1)").
  static std::string numberText(double v);

  /// Parses JSON text that must hold an object. Fails on bad JSON (including numbers out of range, 1e999).
  Json parseObject(const std::string& text) const;
  void checkObject(const Json& j, const std::string& where) const;
  /// Fails naming the first key of `j` that is not in `allowed`, and lists the known keys.
  void checkKeys(const Json& j, const std::set<std::string>& allowed, const std::string& where) const;
  /// The object at `key`, which must be present.
  const Json& object(const Json& j, const std::string& key, const std::string& where) const;

  /// A finite number; `fallback` when absent (or a "is missing" failure when `required`).
  double number(const Json& j, const std::string& key, const std::string& where, double fallback,
                bool required = false) const;
  /// number() that must be > 0.
  double positive(const Json& j, const std::string& key, const std::string& where, double fallback,
                  bool required = false) const;
  /// number() that must be >= 0.
  double nonNegative(const Json& j, const std::string& key, const std::string& where, double fallback,
                     bool required = false) const;
  /// A finite number in [lo, hi] (in (lo, hi] when `lowOpen`); `fallback` when absent (not checked). The
  /// bounds are the plausible range of the quantity: a value outside is a typo or an absurd setting, refused with
  /// one line naming the key and the range before it can blow a run up.
  double ranged(const Json& j, const std::string& key, const std::string& where, double fallback, double lo, double hi,
                bool lowOpen = false) const;
  /// A vec3 whose components each lie in [-bound, bound]; `fallback` when absent.
  Vec3 boundedVec3(const Json& j, const std::string& key, const std::string& where, const Vec3& fallback,
                   double bound) const;
  /// An integer in lo..hi; `fallback` when absent. Checked as a JSON integer before any cast (a 1e300 or a
  /// 2^64 is an error, never an out-of-range conversion).
  int integer(const Json& j, const std::string& key, const std::string& where, int fallback, int lo, int hi) const;
  bool boolean(const Json& j, const std::string& key, const std::string& where, bool fallback) const;
  /// A string; "" when absent.
  std::string string(const Json& j, const std::string& key, const std::string& where) const;
  /// An array of exactly `count` finite numbers (the key must be present).
  std::vector<double> numbers(const Json& j, const std::string& key, const std::string& where, std::size_t count) const;
  /// [x, y, z] of finite numbers; `fallback` when absent (or a "is missing" failure when `required`).
  Vec3 vec3(const Json& j, const std::string& key, const std::string& where, const Vec3& fallback,
            bool required = false) const;
  /// [w, x, y, z] of norm 1 within 1e-6, normalized (the key must be present).
  Quat unitQuaternion(const Json& j, const std::string& key, const std::string& where) const;
  /// A file path (see the file comment); "" when absent. Fails when it is found nowhere and files are required.
  std::string file(const Json& j, const std::string& key, const std::string& where) const;

 private:
  std::string m_scene;
  SceneFileSearch m_search;
};

}  // namespace sdfccd::detail
