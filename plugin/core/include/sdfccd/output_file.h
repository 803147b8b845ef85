/// @file
/// @brief OutputFile: how every sdfccd output is written — complete or not at all, never through a planted
/// link, never over one of the command's inputs.
///
/// @details The policy follows coreutils `cp`/`install`, moreutils `sponge` and Python's `atomicwrites`:
/// - The path the user names is resolved first: a symbolic link is followed, link by link (relative links
///   against their own folder), and the file it ends at is the target, as `cp` does. A dangling link creates
///   the file it points to. As the kernel's fs.protected_symlinks does, a link in a world-writable sticky
///   folder (/tmp) that belongs to another user is refused rather than followed.
/// - A regular target, or a new file, is written to a temporary file in the target's folder whose name is the
///   target's plus ".tmp-" and 12 random characters (71 bits from getrandom), created with
///   O_CREAT | O_EXCL | O_NOFOLLOW and mode 0600: a link or file planted at any name makes the open fail and a
///   new name is drawn, so nothing but the target ever changes. commit() flushes, fsyncs, gives the file the
///   target's mode (and, where allowed, its owner and group) — or 0666 & ~umask for a new file, like any
///   create — renames it over the target (atomic within a folder) and fsyncs the folder. A reader sees the
///   old file or the new one, never a mix; an error or an exception before commit() leaves the old target
///   untouched and removes the temporary file (RAII).
/// - A target that exists and is not a regular file (a character device such as /dev/null, a FIFO, a
///   terminal) is opened and written directly, never replaced, and "-" is standard output. These outputs
///   are not atomic: an error leaves what was already written.
/// - In a program that calls installTempFileCleanupHandlers() (the sdfccd tool does, at start-up), a
///   terminating signal (SIGINT, SIGTERM, SIGHUP, SIGPIPE) removes every live temporary file before the
///   process ends by that signal. The library itself installs no signal handler. SIGKILL cannot be caught: a
///   leftover "*.tmp-*" file then is garbage that is safe to delete.
/// - checkOutput(), called by a command before any work, refuses an output that is one of its inputs (the
///   same device and inode, so through links and hard links too) and one that cannot be created.
///
/// Replacing a file gives it a new inode: other hard links to the old target keep the old contents, as with
/// `install` (and unlike `cp`, which writes in place and can leave a half-written file).
///
/// Thread safety: one OutputFile is used by one thread at a time; different OutputFiles may be written from
/// different threads.
#pragma once

#include <memory>
#include <ostream>
#include <string>
#include <vector>

namespace sdfccd {

/// An output being written; see the file comment for the policy. Errors throw sdfccd::Error with one line
/// naming the path the caller gave.
class OutputFile {
 public:
  /// Resolves `path` ("-": standard output) and opens the temporary file or the non-regular target.
  explicit OutputFile(std::string path);
  /// Without a successful commit(): closes and removes the temporary file; the old target is untouched.
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  /// The stream to write to (binary: no newline translation). A failed write sets badbit; commit() reports
  /// it with the system's reason.
  std::ostream& stream();
  /// Flushes and checks every write, then moves the output into place (see the file comment). Throws
  /// sdfccd::Error on failure, after which the temporary file is gone and the old target untouched.
  void commit();
  /// The path as the caller gave it (used in messages).
  const std::string& path() const;
  /// The file actually written: `path()` with its links followed.
  const std::string& targetPath() const;
  /// True when the target is replaced by rename; false when it is written directly (device, FIFO, "-").
  bool replacesTarget() const;

 private:
  struct State;
  std::unique_ptr<State> m_state;
};

/// Installs, for SIGINT, SIGTERM, SIGHUP and SIGPIPE, a handler that removes the live temporary files and the
/// empty folders that OutputFile and OutputFolder objects of this process created, then ends the process by that
/// signal (exit status 128 + N in a shell). Only a signal whose disposition is still the default gets it: a
/// signal the parent ignores (nohup, a background job) stays ignored, and a handler the program installed is
/// kept. For programs, at start-up; the library never calls it. Calling it again changes nothing.
void installTempFileCleanupHandlers();

/// Writes `contents` to `path` through an OutputFile.
void writeOutputFile(const std::string& path, const std::string& contents);

/// The checks a command makes before any work, so that a bad output fails in a second, not after an hour:
/// - refuses `output` when it is the same file (device and inode, links followed; for "-" the file standard
///   output goes to) as one of `inputs` (inputs that do not exist are skipped: their loader reports them);
/// - refuses an output that cannot be written: a folder, a non-regular file without write permission, or a
///   folder in which no temporary file can be created (tried, then removed; a FIFO is never opened here,
///   since opening it would wait for a reader).
/// Throws sdfccd::Error with one line naming the output (and the input it matched).
void checkOutput(const std::string& output, const std::vector<std::string>& inputs = {});

}  // namespace sdfccd
