/// @file
/// @brief Shell files: ascii PLY and CSV of positions and normals (see point_shell.h). Areas are not stored.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "sdfccd/error.h"
#include "sdfccd/output_file.h"
#include "sdfccd/shell/point_shell.h"
#include "sdfccd/tolerances.h"

namespace sdfccd {
namespace {

std::string lowerExtension(const std::string& path) {
  const auto dot = path.find_last_of('.');
  const auto slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot + 1);
  for (auto& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return ext;
}

bool parseDouble(const std::string& token, double& out) {
  if (token.empty()) return false;
  char* end = nullptr;
  out = std::strtod(token.c_str(), &end);
  return end == token.c_str() + token.size();
}

std::vector<std::string> splitTokens(const std::string& line, char separator) {
  std::vector<std::string> tokens;
  if (separator == ' ') {
    std::istringstream in(line);
    for (std::string t; in >> t;) tokens.push_back(t);
    return tokens;
  }
  std::string current;
  for (char ch : line) {
    if (ch == separator) {
      tokens.push_back(current);
      current.clear();
    } else if (ch != ' ' && ch != '\t' && ch != '\r') {
      current += ch;
    }
  }
  tokens.push_back(current);
  return tokens;
}

bool isBlank(const std::string& line) {
  return std::all_of(line.begin(), line.end(), [](char ch) { return std::isspace(static_cast<unsigned char>(ch)); });
}

// Checks and normalizes one point read from `where`.
void addPoint(PointShell& shell, const double v[6], const std::string& where) {
  const Vec3 p(v[0], v[1], v[2]);
  const Vec3 n(v[3], v[4], v[5]);
  if (!p.allFinite() || !n.allFinite()) throw Error(where + ": non-finite value");
  const double length = n.norm();
  if (!(length > tolerance::kMinDirectionLength)) throw Error(where + ": zero-length normal");
  shell.positions.push_back(p);
  shell.normals.push_back(n / length);
}

PointShell loadPly(std::istream& in, const std::string& path) {
  std::string line;
  int lineNo = 0;
  auto next = [&](std::string& out) {
    if (!std::getline(in, out)) return false;
    ++lineNo;
    if (!out.empty() && out.back() == '\r') out.pop_back();
    return true;
  };
  if (!next(line) || line != "ply") throw Error(path + ": not a PLY file (no 'ply' magic on line 1)");
  long long count = -1;
  bool inVertex = false;
  bool vertexFirst = false;
  bool otherElements = false;
  std::vector<std::string> properties;
  bool ended = false;
  while (next(line)) {
    const auto tokens = splitTokens(line, ' ');
    if (tokens.empty() || tokens[0] == "comment" || tokens[0] == "obj_info") continue;
    if (tokens[0] == "format") {
      if (tokens.size() < 2 || tokens[1] != "ascii") {
        throw Error(path + ":" + std::to_string(lineNo) + ": only ascii PLY shells are supported");
      }
    } else if (tokens[0] == "element") {
      if (tokens.size() != 3) throw Error(path + ":" + std::to_string(lineNo) + ": malformed element line");
      if (tokens[1] == "vertex") {
        if (otherElements) throw Error(path + ": the vertex element must come first");
        vertexFirst = true;
        inVertex = true;
        char* end = nullptr;
        count = std::strtoll(tokens[2].c_str(), &end, 10);
        if (end != tokens[2].c_str() + tokens[2].size() || count < 0) {
          throw Error(path + ":" + std::to_string(lineNo) + ": bad vertex count '" + tokens[2] + "'");
        }
      } else {
        inVertex = false;
        if (tokens[2] != "0") otherElements = true;
      }
    } else if (tokens[0] == "property") {
      if (inVertex) {
        if (tokens.size() != 3 || tokens[1] == "list") {
          throw Error(path + ":" + std::to_string(lineNo) + ": unsupported vertex property");
        }
        properties.push_back(tokens[2]);
      }
    } else if (tokens[0] == "end_header") {
      ended = true;
      break;
    } else {
      throw Error(path + ":" + std::to_string(lineNo) + ": unexpected header line '" + line + "'");
    }
  }
  if (!ended) throw Error(path + ": truncated PLY header (no end_header)");
  if (!vertexFirst || count < 0) throw Error(path + ": no vertex element");
  if (count == 0) throw Error(path + ": the shell has no points");
  if (count > 200000000) throw Error(path + ": absurd vertex count " + std::to_string(count));
  const char* names[6] = {"x", "y", "z", "nx", "ny", "nz"};
  int column[6];
  for (int k = 0; k < 6; ++k) {
    const auto it = std::find(properties.begin(), properties.end(), names[k]);
    if (it == properties.end()) throw Error(path + ": the vertex element has no '" + names[k] + "' property");
    column[k] = static_cast<int>(it - properties.begin());
  }
  PointShell shell;
  // The header's count is not trusted for memory: a 200-byte file claiming 10^8 points would reserve 5 GB
  // before its truncation is found (found by tests/fuzz/fuzz_shell_loader). The vectors grow as points come.
  const std::size_t reserved = static_cast<std::size_t>(std::min<long long>(count, 1 << 16));
  shell.positions.reserve(reserved);
  shell.normals.reserve(reserved);
  for (long long n = 0; n < count; ++n) {
    if (!next(line)) {
      throw Error(path + ": truncated, expected " + std::to_string(count) + " points, found " + std::to_string(n));
    }
    const auto tokens = splitTokens(line, ' ');
    const std::string where = path + ":" + std::to_string(lineNo);
    if (tokens.size() != properties.size()) {
      throw Error(where + ": expected " + std::to_string(properties.size()) + " values, found " +
                  std::to_string(tokens.size()));
    }
    double v[6];
    for (int k = 0; k < 6; ++k) {
      if (!parseDouble(tokens[column[k]], v[k])) throw Error(where + ": not a number '" + tokens[column[k]] + "'");
    }
    addPoint(shell, v, where);
  }
  if (!otherElements) {
    while (next(line)) {
      if (!isBlank(line)) {
        throw Error(path + ":" + std::to_string(lineNo) + ": more points than the header's " + std::to_string(count));
      }
    }
  }
  return shell;
}

PointShell loadCsv(std::istream& in, const std::string& path) {
  std::string line;
  int lineNo = 0;
  bool header = false;
  PointShell shell;
  while (std::getline(in, line)) {
    ++lineNo;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (isBlank(line)) continue;
    const auto tokens = splitTokens(line, ',');
    const std::string where = path + ":" + std::to_string(lineNo);
    if (!header) {
      if (tokens != std::vector<std::string>{"x", "y", "z", "nx", "ny", "nz"}) {
        throw Error(where + ": expected the header 'x,y,z,nx,ny,nz'");
      }
      header = true;
      continue;
    }
    if (tokens.size() != 6) throw Error(where + ": expected 6 values, found " + std::to_string(tokens.size()));
    double v[6];
    for (int k = 0; k < 6; ++k) {
      if (!parseDouble(tokens[k], v[k])) throw Error(where + ": not a number '" + tokens[k] + "'");
    }
    addPoint(shell, v, where);
  }
  if (!header) throw Error(path + ": empty file (no 'x,y,z,nx,ny,nz' header)");
  if (shell.empty()) throw Error(path + ": the shell has no points");
  return shell;
}

}  // namespace

void saveShell(const PointShell& shell, const std::string& path) {
  shell.validate();
  if (shell.empty()) throw Error("saveShell: the shell has no points");
  const std::string ext = lowerExtension(path);
  if (ext != "ply" && ext != "csv") throw Error(path + ": unknown shell format (use .ply or .csv)");
  OutputFile file(path);
  auto& out = file.stream();
  out << std::setprecision(std::numeric_limits<double>::max_digits10);
  if (ext == "ply") {
    out << "ply\nformat ascii 1.0\ncomment sdfccd point shell (body frame, unit outward normals)\n"
        << "element vertex " << shell.size() << "\n"
        << "property double x\nproperty double y\nproperty double z\n"
        << "property double nx\nproperty double ny\nproperty double nz\nend_header\n";
    for (std::size_t n = 0; n < shell.size(); ++n) {
      const Vec3& p = shell.positions[n];
      const Vec3& q = shell.normals[n];
      out << p.x() << ' ' << p.y() << ' ' << p.z() << ' ' << q.x() << ' ' << q.y() << ' ' << q.z() << '\n';
    }
  } else {
    out << "x,y,z,nx,ny,nz\n";
    for (std::size_t n = 0; n < shell.size(); ++n) {
      const Vec3& p = shell.positions[n];
      const Vec3& q = shell.normals[n];
      out << p.x() << ',' << p.y() << ',' << p.z() << ',' << q.x() << ',' << q.y() << ',' << q.z() << '\n';
    }
  }
  file.commit();
}

PointShell parseShell(const std::string& text, const std::string& name) {
  const std::string ext = lowerExtension(name);
  if (ext != "ply" && ext != "csv") throw Error(name + ": unknown shell format (use .ply or .csv)");
  std::istringstream in(text);
  return ext == "ply" ? loadPly(in, name) : loadCsv(in, name);
}

PointShell loadShell(const std::string& path) {
  const std::string ext = lowerExtension(path);
  if (ext != "ply" && ext != "csv") throw Error(path + ": unknown shell format (use .ply or .csv)");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open the shell file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw Error(path + ": cannot read the shell file");
  return parseShell(text.str(), path);
}

}  // namespace sdfccd
