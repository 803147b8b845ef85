/// @file
/// @brief The live temporary files of this process, and the output folders it created, removed when SIGINT,
/// SIGTERM, SIGHUP or SIGPIPE ends it. Internal header of OutputFile and OutputFolder.
///
/// @details A fixed table of slots in static storage: registering copies the path into a free slot, and the
/// signal handler walks the table with async-signal-safe calls only (lock-free atomics, unlink(2), then
/// rmdir(2) of the folders, longest path first so that children go before their parents; rmdir removes only
/// an empty folder, so a folder that holds anything stays), then
/// restores the default action and raises the signal again, so the process still ends by that signal (exit
/// status 128 + N in a shell). Each slot has a state: free, being filled, live, or taken by the handler; the
/// handler claims a live slot with a compare-and-swap before it reads the path, so a thread that frees or
/// reuses a slot at the same moment never hands it a half-written path.
///
/// The library registers and forgets paths but installs no handler: a program that wants the cleanup calls
/// sdfccd::installTempFileCleanupHandlers() (sdfccd/output_file.h) at start-up, as the sdfccd tool does.
#pragma once

namespace sdfccd::detail {

/// Records `path` (made absolute with the working folder of this moment) as a temporary file to remove if a terminating
/// signal arrives. Returns the slot to pass to unregisterTempFile(), or -1 when the path does not fit or every slot is
/// taken (the file then simply is not cleaned up on a signal; RAII still removes it on every other path).
int registerTempFile(const char* path);

/// Records `path` as a folder this process created, to rmdir (only if empty) on a terminating signal. Same
/// contract as registerTempFile().
int registerTempFolder(const char* path);

/// Forgets a slot returned by registerTempFile() or registerTempFolder() (-1 is ignored). Call it after the file was
/// renamed or unlinked, never before: a signal in between then unlinks a name that no longer exists, which is harmless.
void unregisterTempFile(int slot);

/// How many slots (files and folders) are live now (for tests).
int liveTempFileCount();

}  // namespace sdfccd::detail
