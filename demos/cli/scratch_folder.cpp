/// @file
/// @brief ScratchFolder: mkdtemp under $TMPDIR; moveToOutput through OutputFile.
#include "cli/scratch_folder.h"

#include <stdlib.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "sdfccd/error.h"
#include "sdfccd/output_file.h"

namespace sdfccd::cli {

ScratchFolder::ScratchFolder() {
  const char* tmp = std::getenv("TMPDIR");
  std::string pattern = std::string(tmp != nullptr && tmp[0] == '/' ? tmp : "/tmp") + "/sdfccd-scratch-XXXXXX";
  if (::mkdtemp(pattern.data()) == nullptr) {
    throw Error("cannot create a scratch folder '" + pattern + "': " + std::strerror(errno));
  }
  m_path = pattern;
}

ScratchFolder::~ScratchFolder() {
  std::error_code ignored;
  std::filesystem::remove_all(m_path, ignored);
}

void moveToOutput(const std::string& scratchFile, const std::string& output) {
  {
    std::ifstream in(scratchFile, std::ios::binary);
    if (!in) throw Error("cannot read '" + scratchFile + "' to write '" + output + "': " + std::strerror(errno));
    OutputFile file(output);
    if (in.peek() != std::ifstream::traits_type::eof()) file.stream() << in.rdbuf();
    if (in.bad()) throw Error("cannot read '" + scratchFile + "' to write '" + output + "'");
    file.commit();
  }
  ::unlink(scratchFile.c_str());
}

}  // namespace sdfccd::cli
