/// @file
/// @brief OutputFile: link resolution, the O_EXCL | O_NOFOLLOW temporary file, commit by rename, direct
/// writes to devices and FIFOs, and the checks made before any work.
#include "sdfccd/output_file.h"

#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <random>
#include <streambuf>

#include "sdfccd/error.h"
#include "temp_file_registry.h"

namespace sdfccd {
namespace {

std::string systemError(int error) {
  return std::strerror(error);
}

}  // namespace

namespace detail {

/// A streambuf over a file descriptor: std::ofstream cannot open with O_EXCL | O_NOFOLLOW. Writes retry
/// on EINTR and short writes; the first failure is kept (errno) and fails every later write. In a named
/// namespace (not the file's anonymous one): OutputFile::State, a member of a public class, holds one.
class FdStreamBuf : public std::streambuf {
 public:
  void attach(int fd) {
    m_fd = fd;
    setp(m_buffer.data(), m_buffer.data() + m_buffer.size());
  }
  int error() const { return m_error; }

 protected:
  int_type overflow(int_type c) override {
    if (!flushBuffer()) return traits_type::eof();
    if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
    *pptr() = traits_type::to_char_type(c);
    pbump(1);
    return c;
  }
  std::streamsize xsputn(const char* data, std::streamsize count) override {
    if (count < epptr() - pptr()) {
      std::memcpy(pptr(), data, static_cast<std::size_t>(count));
      pbump(static_cast<int>(count));
      return count;
    }
    if (!flushBuffer() || !writeAll(data, static_cast<std::size_t>(count))) return 0;
    return count;
  }
  int sync() override { return flushBuffer() ? 0 : -1; }

 private:
  bool flushBuffer() {
    const std::size_t pending = static_cast<std::size_t>(pptr() - pbase());
    setp(m_buffer.data(), m_buffer.data() + m_buffer.size());
    return writeAll(m_buffer.data(), pending);
  }
  bool writeAll(const char* data, std::size_t size) {
    if (m_error != 0 || m_fd < 0) {
      if (m_error == 0) m_error = EBADF;
      return false;
    }
    while (size > 0) {
      const ssize_t written = ::write(m_fd, data, size);
      if (written < 0 && errno == EINTR) continue;
      if (written <= 0) {
        m_error = written < 0 ? errno : EIO;
        return false;
      }
      data += written;
      size -= static_cast<std::size_t>(written);
    }
    return true;
  }

  int m_fd = -1;
  int m_error = 0;
  std::array<char, 1 << 16> m_buffer{};
};

}  // namespace detail

namespace {

/// The folder part of a path ("." for a bare name).
std::string folderOf(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  if (slash == 0) return "/";
  return path.substr(0, slash);
}

std::string nameOf(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

/// Where an output path leads once its links are followed.
struct ResolvedOutput {
  std::string target;
  bool exists = false;
  struct stat info {};
};

/// The kernel's fs.protected_symlinks rule, applied to the links we follow ourselves: in a world-writable
/// sticky folder, follow a link only if it is ours or the folder owner's.
void refuseForeignLinkInStickyFolder(const std::string& userPath, const std::string& link, const struct stat& info) {
  struct stat folder {};
  if (::stat(folderOf(link).c_str(), &folder) != 0) return;
  const bool stickyAndShared = (folder.st_mode & S_ISVTX) && (folder.st_mode & S_IWOTH);
  if (stickyAndShared && info.st_uid != ::geteuid() && info.st_uid != folder.st_uid) {
    throw Error("refusing to write '" + userPath + "': '" + link +
                "' is another user's symbolic link in a world-writable sticky folder");
  }
}

ResolvedOutput resolveOutput(const std::string& userPath) {
  if (userPath.empty()) throw Error("an output path is empty");
  ResolvedOutput out;
  out.target = userPath;
  for (int links = 0;; ++links) {
    if (::lstat(out.target.c_str(), &out.info) != 0) {
      if (errno == ENOENT) return out;  // a new file (a missing folder is reported when creating it)
      throw Error("cannot write '" + userPath + "': " + systemError(errno));
    }
    if (!S_ISLNK(out.info.st_mode)) {
      out.exists = true;
      if (S_ISDIR(out.info.st_mode)) throw Error("cannot write '" + userPath + "': it is a folder");
      return out;
    }
    if (links >= 40) throw Error("cannot write '" + userPath + "': " + systemError(ELOOP));
    refuseForeignLinkInStickyFolder(userPath, out.target, out.info);
    std::array<char, PATH_MAX> buffer{};
    const ssize_t length = ::readlink(out.target.c_str(), buffer.data(), buffer.size());
    if (length <= 0 || static_cast<std::size_t>(length) >= buffer.size()) {
      throw Error("cannot write '" + userPath + "': cannot read the link '" + out.target + "'");
    }
    const std::string link(buffer.data(), static_cast<std::size_t>(length));
    out.target = link.front() == '/' ? link : folderOf(out.target) + "/" + link;
  }
}

/// 12 characters from [0-9A-Za-z]: about 71 bits, from getrandom (std::random_device if it is missing).
std::string randomSuffix() {
  static const char kAlphabet[] = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz";
  std::array<unsigned char, 12> bytes{};
  if (::getrandom(bytes.data(), bytes.size(), 0) != static_cast<ssize_t>(bytes.size())) {
    std::random_device device;
    for (unsigned char& b : bytes) b = static_cast<unsigned char>(device());
  }
  std::string suffix;
  for (const unsigned char b : bytes) suffix += kAlphabet[b % 62];
  return suffix;
}

/// A temporary file beside `target`: a fresh random name, O_CREAT | O_EXCL | O_NOFOLLOW, mode 0600. A name
/// that exists (a planted link, a file, a collision) makes the open fail and the next name is drawn. The
/// name is registered for removal on a terminating signal; the signals are blocked in this thread from the
/// open to the registration, so an interrupt cannot come between the two here.
int createTempFile(const std::string& userPath, const std::string& target, std::string& outTempPath, int& outSlot) {
  // Long names are shortened so that the suffix still fits in NAME_MAX (255 bytes).
  std::string stem = nameOf(target);
  if (stem.size() > 200) stem.resize(200);
  const std::string folder = folderOf(target);
  sigset_t terminating, previous;
  sigemptyset(&terminating);
  for (const int s : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) sigaddset(&terminating, s);
  for (int attempt = 0; attempt < 100; ++attempt) {
    const std::string candidate = folder + "/" + stem + ".tmp-" + randomSuffix();
    ::pthread_sigmask(SIG_BLOCK, &terminating, &previous);
    const int fd = ::open(candidate.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
    const int error = errno;
    if (fd >= 0) outSlot = detail::registerTempFile(candidate.c_str());
    ::pthread_sigmask(SIG_SETMASK, &previous, nullptr);
    if (fd >= 0) {
      outTempPath = candidate;
      return fd;
    }
    if (error != EEXIST && error != ELOOP && error != EINTR) {
      throw Error("cannot write '" + userPath + "': cannot create a file in '" + folder + "': " + systemError(error));
    }
  }
  throw Error("cannot write '" + userPath + "': no free temporary name in '" + folder + "' after 100 tries");
}

/// The process's umask, read without changing it (/proc/self/status, Linux 4.7+); otherwise set and
/// restored at once (racy only against another thread creating a file in that instant).
mode_t currentUmask() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);) {
    if (line.rfind("Umask:", 0) == 0) return static_cast<mode_t>(std::strtoul(line.c_str() + 6, nullptr, 8) & 0777);
  }
  const mode_t mask = ::umask(022);
  ::umask(mask);
  return mask;
}

bool sameFile(const struct stat& a, const struct stat& b) {
  return a.st_dev == b.st_dev && a.st_ino == b.st_ino;
}

}  // namespace

struct OutputFile::State {
  std::string path;
  std::string target;
  std::string tempPath;  // empty when the target is written directly
  int fd = -1;
  bool ownsFd = true;  // false for standard output
  int slot = -1;
  bool finished = false;
  detail::FdStreamBuf buffer;
  std::ostream stream{&buffer};

  /// Closes and removes the temporary file (idempotent).
  void discard() {
    if (finished) return;
    finished = true;
    if (fd >= 0 && ownsFd) ::close(fd);
    fd = -1;
    if (!tempPath.empty()) {
      ::unlink(tempPath.c_str());
      detail::unregisterTempFile(slot);
    }
  }
};

OutputFile::OutputFile(std::string path) : m_state(std::make_unique<State>()) {
  State& s = *m_state;
  s.path = std::move(path);
  if (s.path == "-") {
    s.target = s.path;
    s.fd = STDOUT_FILENO;
    s.ownsFd = false;
  } else {
    const ResolvedOutput resolved = resolveOutput(s.path);
    s.target = resolved.target;
    if (resolved.exists && !S_ISREG(resolved.info.st_mode)) {
      // A device, FIFO or socket: written in place. O_NOFOLLOW: if it was swapped for a link since, fail.
      s.fd = ::open(s.target.c_str(), O_WRONLY | O_NOCTTY | O_NOFOLLOW | O_CLOEXEC);
      if (s.fd < 0) throw Error("cannot write '" + s.path + "': " + systemError(errno));
      struct stat opened {};
      if (::fstat(s.fd, &opened) != 0 || S_ISREG(opened.st_mode)) {
        ::close(s.fd);
        throw Error("cannot write '" + s.path + "': it changed while being opened");
      }
    } else {
      s.fd = createTempFile(s.path, s.target, s.tempPath, s.slot);
    }
  }
  s.buffer.attach(s.fd);
}

OutputFile::~OutputFile() {
  if (m_state) m_state->discard();
}

std::ostream& OutputFile::stream() {
  return m_state->stream;
}
const std::string& OutputFile::path() const {
  return m_state->path;
}
const std::string& OutputFile::targetPath() const {
  return m_state->target;
}
bool OutputFile::replacesTarget() const {
  return !m_state->tempPath.empty();
}

void OutputFile::commit() {
  State& s = *m_state;
  if (s.finished) throw Error("'" + s.path + "' was already committed or discarded");
  s.stream.flush();
  if (!s.stream || s.buffer.error() != 0) {
    const int error = s.buffer.error() != 0 ? s.buffer.error() : EIO;
    s.discard();
    throw Error("cannot write '" + s.path + "': " + systemError(error));
  }
  if (s.tempPath.empty()) {
    // Direct output: nothing to move. Standard output stays open for the rest of the program.
    const int fd = s.fd;
    const bool owns = s.ownsFd;
    s.fd = -1;
    s.finished = true;
    if (owns && ::close(fd) != 0 && errno != EINTR) {
      throw Error("cannot write '" + s.path + "': " + systemError(errno));
    }
    return;
  }
  // The target's permissions (its owner and group first where allowed: chown clears set-id bits), or those
  // of a newly created file.
  struct stat old {};
  mode_t mode = 0666 & ~currentUmask();
  if (::stat(s.target.c_str(), &old) == 0 && S_ISREG(old.st_mode)) {
    if ((old.st_uid != ::geteuid() || old.st_gid != ::getegid()) && ::fchown(s.fd, old.st_uid, old.st_gid) != 0) {
      (void)::fchown(s.fd, static_cast<uid_t>(-1), old.st_gid);  // the group alone, if we are a member
    }
    mode = old.st_mode & 07777;
  }
  if (::fchmod(s.fd, mode) != 0 || ::fsync(s.fd) != 0) {
    const int error = errno;
    s.discard();
    throw Error("cannot write '" + s.path + "': " + systemError(error));
  }
  const int fd = s.fd;
  s.fd = -1;
  if (::close(fd) != 0 && errno != EINTR) {
    const int error = errno;
    s.discard();
    throw Error("cannot write '" + s.path + "': " + systemError(error));
  }
  if (::rename(s.tempPath.c_str(), s.target.c_str()) != 0) {
    const int error = errno;
    s.discard();
    throw Error("cannot move the output into place at '" + s.path + "': " + systemError(error));
  }
  s.finished = true;
  detail::unregisterTempFile(s.slot);
  // The rename itself is durable once the folder is synced (a failure here loses nothing yet written).
  const int folder = ::open(folderOf(s.target).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (folder >= 0) {
    (void)::fsync(folder);
    ::close(folder);
  }
}

void writeOutputFile(const std::string& path, const std::string& contents) {
  OutputFile file(path);
  file.stream().write(contents.data(), static_cast<std::streamsize>(contents.size()));
  file.commit();
}

void checkOutput(const std::string& output, const std::vector<std::string>& inputs) {
  struct stat outputInfo {};
  bool outputExists = false;
  ResolvedOutput resolved;
  if (output == "-") {
    outputExists = ::fstat(STDOUT_FILENO, &outputInfo) == 0;
  } else {
    resolved = resolveOutput(output);
    outputExists = resolved.exists;
    outputInfo = resolved.info;
  }
  if (outputExists) {
    for (const std::string& input : inputs) {
      struct stat inputInfo {};
      if (::stat(input.c_str(), &inputInfo) == 0 && sameFile(inputInfo, outputInfo)) {
        const std::string what = output == "-" ? "standard output" : "'" + output + "'";
        throw Error("refusing to write " + what + ": it is the input '" + input + "'");
      }
    }
  }
  if (output == "-") return;
  if (resolved.exists && !S_ISREG(resolved.info.st_mode)) {
    if (::access(resolved.target.c_str(), W_OK) != 0) {
      throw Error("cannot write '" + output + "': " + systemError(errno));
    }
    return;
  }
  std::string tempPath;
  int slot = -1;
  const int fd = createTempFile(output, resolved.target, tempPath, slot);
  ::close(fd);
  ::unlink(tempPath.c_str());
  detail::unregisterTempFile(slot);
}

}  // namespace sdfccd
