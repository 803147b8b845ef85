/// @file
/// @brief fnv1a: the project's one 64-bit FNV-1a hash (SDF file checksums, model cache keys, the golden state
/// hash of a scene run).
///
/// @details Written out because std::hash is neither specified nor stable across library versions, and the core
/// depends on Eigen alone (no zlib crc32). FNV-1a is a dozen lines with a published specification
/// (Fowler, Noll, Vo): for each byte, xor it in, then multiply by the FNV prime. Continue a hash over several
/// buffers by passing the previous result as `hash`.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace sdfccd {

inline constexpr std::uint64_t kFnv1aOffset = 14695981039346656037ull;  ///< FNV-1a 64-bit offset basis
inline constexpr std::uint64_t kFnv1aPrime = 1099511628211ull;          ///< FNV-1a 64-bit prime

/// 64-bit FNV-1a of `size` bytes at `data`, continuing from `hash` (the offset basis starts a new hash).
inline std::uint64_t fnv1a(const void* data, std::size_t size, std::uint64_t hash = kFnv1aOffset) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (std::size_t n = 0; n < size; ++n) {
    hash ^= bytes[n];
    hash *= kFnv1aPrime;
  }
  return hash;
}

/// 64-bit FNV-1a of the bytes of `text`, continuing from `hash`.
inline std::uint64_t fnv1a(std::string_view text, std::uint64_t hash = kFnv1aOffset) {
  return fnv1a(text.data(), text.size(), hash);
}

}  // namespace sdfccd
