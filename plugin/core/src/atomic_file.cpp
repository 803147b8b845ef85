/// @file
/// @brief AtomicFile: temporary file + rename.
#include "sdfccd/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>

#include "sdfccd/error.h"

namespace sdfccd {

namespace {
std::atomic<unsigned> g_tempCounter{0};
}

AtomicFile::AtomicFile(std::string path) : m_path(std::move(path)) {
  m_tempPath = m_path + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(g_tempCounter++);
  m_stream.open(m_tempPath, std::ios::binary | std::ios::trunc);
  if (!m_stream) throw Error("cannot write '" + m_path + "': " + std::strerror(errno));
}

AtomicFile::~AtomicFile() {
  if (!m_committed) {
    m_stream.close();
    std::remove(m_tempPath.c_str());
  }
}

void AtomicFile::commit() {
  m_stream.flush();
  const bool good = static_cast<bool>(m_stream);
  m_stream.close();
  if (!good || m_stream.fail()) {
    std::remove(m_tempPath.c_str());
    m_committed = true;
    throw Error("failed while writing '" + m_path + "'");
  }
  if (std::rename(m_tempPath.c_str(), m_path.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::remove(m_tempPath.c_str());
    m_committed = true;
    throw Error("cannot move the output into place at '" + m_path + "': " + why);
  }
  m_committed = true;
}

void writeFileAtomically(const std::string& path, const std::string& contents) {
  AtomicFile file(path);
  file.stream().write(contents.data(), static_cast<std::streamsize>(contents.size()));
  file.commit();
}

}  // namespace sdfccd
