/// @file
/// @brief Native binary and SDFGen text SDF files: detection, validation, atomic writing.
///
/// @details The checksum is the project's 64-bit FNV-1a (sdfccd/fnv1a.h): sdfccd::core depends on Eigen alone
/// (docs/architecture.md), so zlib's crc32 is not available.
/// Bytes are assembled explicitly as little-endian, so files are portable whatever the host's byte order.
#include "sdfccd/field/sdf_file.h"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

#include "sdfccd/error.h"
#include "sdfccd/fnv1a.h"
#include "sdfccd/output_file.h"

namespace sdfccd {

namespace {

constexpr char kMagic[8] = {'s', 'd', 'f', 'c', 'c', 'd', '\x1a', '\n'};
constexpr std::uint32_t kVersion = 1;
constexpr std::uint32_t kValueTypeFloat32 = 1;
constexpr std::size_t kHeaderBytes = 64;
constexpr std::size_t kChecksumBytes = 8;
constexpr std::uint32_t kMaxNodesPerAxis = 1u << 16;  // far above any sane grid; guards the arithmetic

void putU32(unsigned char* out, std::uint32_t v) {
  for (int b = 0; b < 4; ++b) out[b] = static_cast<unsigned char>(v >> (8 * b));
}
void putU64(unsigned char* out, std::uint64_t v) {
  for (int b = 0; b < 8; ++b) out[b] = static_cast<unsigned char>(v >> (8 * b));
}
void putF64(unsigned char* out, double v) {
  std::uint64_t bits;
  std::memcpy(&bits, &v, 8);
  putU64(out, bits);
}
std::uint32_t getU32(const unsigned char* in) {
  std::uint32_t v = 0;
  for (int b = 0; b < 4; ++b) v |= static_cast<std::uint32_t>(in[b]) << (8 * b);
  return v;
}
std::uint64_t getU64(const unsigned char* in) {
  std::uint64_t v = 0;
  for (int b = 0; b < 8; ++b) v |= static_cast<std::uint64_t>(in[b]) << (8 * b);
  return v;
}
double getF64(const unsigned char* in) {
  const std::uint64_t bits = getU64(in);
  double v;
  std::memcpy(&v, &bits, 8);
  return v;
}

// Streams the native encoding of `grid` to `sink(const unsigned char*, size_t)`.
template <class Sink>
void writeNative(const SdfGrid& grid, Sink&& sink) {
  unsigned char header[kHeaderBytes] = {};
  std::memcpy(header, kMagic, 8);
  putU32(header + 8, kVersion);
  putU32(header + 12, kValueTypeFloat32);
  for (int a = 0; a < 3; ++a) putU32(header + 16 + 4 * a, static_cast<std::uint32_t>(grid.nodeCounts()[a]));
  putU32(header + 28, 0);  // reserved
  for (int a = 0; a < 3; ++a) putF64(header + 32 + 8 * a, grid.origin()[a]);
  putF64(header + 56, grid.spacing());
  std::uint64_t hash = fnv1a(header, kHeaderBytes);
  sink(header, kHeaderBytes);
  const std::vector<float>& values = grid.values();
  constexpr std::size_t kChunk = 1 << 14;
  std::vector<unsigned char> buffer(kChunk * 4);
  for (std::size_t start = 0; start < values.size(); start += kChunk) {
    const std::size_t count = std::min(kChunk, values.size() - start);
    for (std::size_t n = 0; n < count; ++n) {
      std::uint32_t bits;
      std::memcpy(&bits, &values[start + n], 4);
      putU32(buffer.data() + 4 * n, bits);
    }
    hash = fnv1a(buffer.data(), 4 * count, hash);
    sink(buffer.data(), 4 * count);
  }
  unsigned char tail[kChecksumBytes];
  putU64(tail, hash);
  sink(tail, kChecksumBytes);
}

template <class Sink>
void writeSdfGen(const SdfGrid& grid, Sink&& sink) {
  std::ostringstream head;
  head.precision(17);
  head << grid.nodeCounts().x() << ' ' << grid.nodeCounts().y() << ' ' << grid.nodeCounts().z() << '\n'
       << grid.origin().x() << ' ' << grid.origin().y() << ' ' << grid.origin().z() << '\n'
       << grid.spacing() << '\n';
  const std::string h = head.str();
  sink(reinterpret_cast<const unsigned char*>(h.data()), h.size());
  std::string buffer;
  buffer.reserve(1 << 16);
  char number[32];
  for (float v : grid.values()) {
    // Shortest representation that reads back to the same float: round trips are exact.
    const auto r = std::to_chars(number, number + sizeof(number), v);
    buffer.append(number, r.ptr);
    buffer.push_back('\n');
    if (buffer.size() > (1 << 16) - 64) {
      sink(reinterpret_cast<const unsigned char*>(buffer.data()), buffer.size());
      buffer.clear();
    }
  }
  sink(reinterpret_cast<const unsigned char*>(buffer.data()), buffer.size());
}

SdfGrid makeGrid(const std::string& name, const Vec3i& counts, const Vec3& origin, double spacing,
                 std::vector<float> values) {
  try {
    return SdfGrid(counts, origin, spacing, std::move(values));
  } catch (const Error& e) {
    throw Error("'" + name + "': " + e.what());
  }
}

SdfGrid parseNative(const std::string& bytes, const std::string& name) {
  auto fail = [&](const std::string& why) { return Error("'" + name + "' is not a valid native SDF file: " + why); };
  if (bytes.size() < kHeaderBytes + kChecksumBytes) {
    throw fail("truncated (" + std::to_string(bytes.size()) + " bytes, the header alone needs " +
               std::to_string(kHeaderBytes + kChecksumBytes) + ")");
  }
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  const std::uint32_t version = getU32(data + 8);
  if (version != kVersion) {
    throw fail("unsupported version " + std::to_string(version) + " (this build reads version " +
               std::to_string(kVersion) + ")");
  }
  if (getU32(data + 12) != kValueTypeFloat32) throw fail("unknown value type " + std::to_string(getU32(data + 12)));
  Vec3i counts;
  std::uint64_t nodes = 1;
  for (int a = 0; a < 3; ++a) {
    const std::uint32_t n = getU32(data + 16 + 4 * a);
    if (n < 2 || n > kMaxNodesPerAxis) throw fail("node count " + std::to_string(n) + " along an axis is out of range");
    counts[a] = static_cast<int>(n);
    nodes *= n;
  }
  const std::uint64_t expected = kHeaderBytes + 4 * nodes + kChecksumBytes;
  if (bytes.size() != expected) {
    std::ostringstream s;
    s << "size " << bytes.size() << " bytes does not match the header (" << counts.x() << " x " << counts.y() << " x "
      << counts.z() << " nodes need " << expected << " bytes)";
    throw fail(s.str());
  }
  const std::uint64_t stored = getU64(data + expected - kChecksumBytes);
  const std::uint64_t actual = fnv1a(data, expected - kChecksumBytes);
  if (stored != actual) throw fail("checksum mismatch (the file is corrupt)");
  const Vec3 origin(getF64(data + 32), getF64(data + 40), getF64(data + 48));
  const double spacing = getF64(data + 56);
  if (!origin.allFinite()) throw fail("origin is not finite");
  if (!std::isfinite(spacing) || spacing <= 0.0) throw fail("spacing must be finite and positive");
  std::vector<float> values(static_cast<std::size_t>(nodes));
  for (std::size_t n = 0; n < values.size(); ++n) {
    const std::uint32_t bits = getU32(data + kHeaderBytes + 4 * n);
    std::memcpy(&values[n], &bits, 4);
    if (!std::isfinite(values[n])) throw fail("value " + std::to_string(n) + " is not finite");
  }
  return makeGrid(name, counts, origin, spacing, std::move(values));
}

// A cursor over SDFGen text that reports the line of each defect.
class TextReader {
 public:
  TextReader(const std::string& text, const std::string& name) : m_text(text), m_name(name) {}

  Error fail(const std::string& why) const {
    return Error("'" + m_name + "' is not a valid SDFGen file: " + why + " (line " + std::to_string(m_line) + ")");
  }
  // Skips whitespace; true if a token follows.
  bool skipSpace() {
    while (m_pos < m_text.size()) {
      const char c = m_text[m_pos];
      if (c == '\n') {
        ++m_line;
      } else if (c != ' ' && c != '\t' && c != '\r' && c != '\v' && c != '\f') {
        return true;
      }
      ++m_pos;
    }
    return false;
  }
  long long readInteger(const char* what) {
    if (!skipSpace()) throw fail(std::string("truncated: missing ") + what);
    const char* begin = m_text.data() + m_pos;
    const char* end = m_text.data() + m_text.size();
    long long v = 0;
    const auto r = std::from_chars(begin, end, v);
    if (r.ec != std::errc() || !endsToken(r.ptr)) throw fail(std::string("expected an integer for ") + what);
    m_pos += static_cast<std::size_t>(r.ptr - begin);
    return v;
  }
  double readReal(const char* what) {
    if (!skipSpace()) throw fail(std::string("truncated: missing ") + what);
    const char* begin = m_text.data() + m_pos;
    const char* end = m_text.data() + m_text.size();
    if (*begin == '+') ++begin;
    double v = 0.0;
    const auto r = std::from_chars(begin, end, v);
    if (r.ec == std::errc::result_out_of_range) throw fail(std::string(what) + " is out of range");
    if (r.ec != std::errc() || !endsToken(r.ptr)) throw fail(std::string("expected a number for ") + what);
    if (!std::isfinite(v)) throw fail(std::string(what) + " is not finite");
    m_pos = static_cast<std::size_t>(r.ptr - m_text.data());
    return v;
  }
  std::size_t remaining() const { return m_text.size() - m_pos; }

 private:
  bool endsToken(const char* p) const {
    if (p == m_text.data() + m_text.size()) return true;
    const char c = *p;
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
  }

  const std::string& m_text;
  const std::string& m_name;
  std::size_t m_pos = 0;
  int m_line = 1;
};

SdfGrid parseSdfGen(const std::string& text, const std::string& name) {
  TextReader reader(text, name);
  Vec3i counts;
  std::uint64_t nodes = 1;
  const char* axes[3] = {"ni", "nj", "nk"};
  for (int a = 0; a < 3; ++a) {
    const long long n = reader.readInteger(axes[a]);
    if (n < 2 || n > static_cast<long long>(kMaxNodesPerAxis)) {
      throw reader.fail(std::string(axes[a]) + " = " + std::to_string(n) + " is out of range (2.." +
                        std::to_string(kMaxNodesPerAxis) + ")");
    }
    counts[a] = static_cast<int>(n);
    nodes *= static_cast<std::uint64_t>(n);
  }
  Vec3 origin;
  origin.x() = reader.readReal("origin x");
  origin.y() = reader.readReal("origin y");
  origin.z() = reader.readReal("origin z");
  const double spacing = reader.readReal("spacing dx");
  if (spacing <= 0.0) throw reader.fail("spacing must be positive");
  // Each value takes at least two bytes (a digit and a separator, the last may lack it): a header that
  // promises more values than the file can hold is rejected before allocating.
  if (nodes > reader.remaining() / 2 + 1) {
    throw reader.fail("truncated: the header promises " + std::to_string(nodes) + " values but only " +
                      std::to_string(reader.remaining()) + " bytes follow");
  }
  std::vector<float> values(static_cast<std::size_t>(nodes));
  for (std::size_t n = 0; n < values.size(); ++n) {
    if (!reader.skipSpace()) {
      throw reader.fail("truncated: expected " + std::to_string(nodes) + " values, found " + std::to_string(n));
    }
    const double v = reader.readReal("a value");
    if (std::fabs(v) > std::numeric_limits<float>::max()) throw reader.fail("a value is out of float range");
    values[n] = static_cast<float>(v);
  }
  if (reader.skipSpace()) throw reader.fail("trailing data after " + std::to_string(nodes) + " values");
  return makeGrid(name, counts, origin, spacing, std::move(values));
}

}  // namespace

const char* toString(SdfFileFormat format) {
  return format == SdfFileFormat::Native ? "native" : "sdfgen";
}

SdfFileFormat parseSdfFileFormat(const std::string& name) {
  if (name == "native") return SdfFileFormat::Native;
  if (name == "sdfgen") return SdfFileFormat::SdfGen;
  throw Error("unknown SDF file format '" + name + "' (expected native or sdfgen)");
}

SdfFileFormat sdfFileFormatForPath(const std::string& path) {
  const std::string ext = ".sdfgen";
  const bool text = path.size() >= ext.size() && path.compare(path.size() - ext.size(), ext.size(), ext) == 0;
  return text ? SdfFileFormat::SdfGen : SdfFileFormat::Native;
}

SdfGrid parseSdf(const std::string& bytes, const std::string& name) {
  if (bytes.empty()) throw Error("'" + name + "' is empty");
  const std::size_t prefix = std::min<std::size_t>(bytes.size(), 8);
  if (std::memcmp(bytes.data(), kMagic, prefix) == 0) return parseNative(bytes, name);
  std::size_t p = 0;
  while (p < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[p]))) ++p;
  if (p < bytes.size() && (std::isdigit(static_cast<unsigned char>(bytes[p])) || bytes[p] == '+')) {
    return parseSdfGen(bytes, name);
  }
  throw Error("'" + name + "' is not an SDF file (neither the native format nor SDFGen text)");
}

std::string serializeSdf(const SdfGrid& grid, SdfFileFormat format) {
  if (grid.empty()) throw Error("cannot write an empty grid");
  std::string out;
  auto sink = [&](const unsigned char* data, std::size_t size) {
    out.append(reinterpret_cast<const char*>(data), size);
  };
  if (format == SdfFileFormat::Native) {
    out.reserve(kHeaderBytes + 4 * grid.values().size() + kChecksumBytes);
    writeNative(grid, sink);
  } else {
    writeSdfGen(grid, sink);
  }
  return out;
}

SdfGrid loadSdf(const std::string& path) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) throw Error("cannot open '" + path + "': " + std::strerror(errno));
  if (!S_ISREG(info.st_mode)) throw Error("cannot read '" + path + "': not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open '" + path + "': " + std::strerror(errno));
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) throw Error("cannot read '" + path + "' (not a regular file?)");
  in.seekg(0, std::ios::beg);
  std::string bytes(static_cast<std::size_t>(size), '\0');
  if (size > 0 && !in.read(bytes.data(), size)) throw Error("cannot read '" + path + "'");
  return parseSdf(bytes, path);
}

void saveSdf(const std::string& path, const SdfGrid& grid, SdfFileFormat format) {
  if (grid.empty()) throw Error("cannot write an empty grid to '" + path + "'");
  OutputFile file(path);
  std::ostream& stream = file.stream();
  auto sink = [&](const unsigned char* data, std::size_t size) {
    stream.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  };
  if (format == SdfFileFormat::Native) {
    writeNative(grid, sink);
  } else {
    writeSdfGen(grid, sink);
  }
  file.commit();
}

}  // namespace sdfccd
