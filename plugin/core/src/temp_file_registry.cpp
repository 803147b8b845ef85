/// @file
/// @brief The table of live temporary files and created folders, and the signal handler that removes them.
#include "temp_file_registry.h"

#include <limits.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>

#include "sdfccd/output_file.h"

namespace sdfccd::detail {
namespace {

static_assert(ATOMIC_INT_LOCK_FREE == 2, "the signal handler needs lock-free atomics");

enum SlotState : int { kFree = 0, kFilling = 1, kLive = 2, kTakenByHandler = 3 };

constexpr int kSlotCount = 64;  // outputs open at once: a command writes a handful, a report a few dozen

struct Slot {
  std::atomic<int> state{kFree};
  bool isFolder = false;  // written before the slot turns live
  pid_t owner = 0;        // the process that registered it: a forked child (before its exec) leaves it alone
  char path[PATH_MAX];
};

Slot g_slots[kSlotCount];

constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP, SIGPIPE};

void removeTempFilesAndReraise(int signalNumber) {
  const int savedErrno = errno;
  bool taken[kSlotCount] = {};
  const pid_t self = ::getpid();
  for (int n = 0; n < kSlotCount; ++n) {
    int expected = kLive;
    if (!g_slots[n].state.compare_exchange_strong(expected, kTakenByHandler)) continue;
    if (g_slots[n].owner != self) {  // the parent's, inherited by fork
      g_slots[n].state.store(kLive);
      continue;
    }
    taken[n] = true;
    if (!g_slots[n].isFolder) ::unlink(g_slots[n].path);
  }
  // Folders after the files in them, the longest path first: a child before its parent.
  for (;;) {
    int longest = -1;
    std::size_t longestLength = 0;
    for (int n = 0; n < kSlotCount; ++n) {
      if (!taken[n] || !g_slots[n].isFolder) continue;
      const std::size_t length = std::strlen(g_slots[n].path);
      if (longest < 0 || length > longestLength) {
        longest = n;
        longestLength = length;
      }
    }
    if (longest < 0) break;
    ::rmdir(g_slots[longest].path);
    taken[longest] = false;
  }
  // The default action, then the same signal again: it is blocked while this handler runs, so it is
  // delivered as soon as the handler returns and ends the process the way the sender meant.
  struct sigaction defaultAction {};
  defaultAction.sa_handler = SIG_DFL;
  sigemptyset(&defaultAction.sa_mask);
  ::sigaction(signalNumber, &defaultAction, nullptr);
  ::raise(signalNumber);
  errno = savedErrno;
}

int registerPath(const char* path, bool isFolder) {
  // Absolute, so that the handler removes the right file whatever the working folder is by then.
  char absolute[PATH_MAX];
  std::size_t prefix = 0;
  if (path[0] != '/') {
    if (::getcwd(absolute, sizeof absolute) == nullptr) return -1;
    prefix = std::strlen(absolute);
    if (prefix + 1 >= sizeof absolute) return -1;
    absolute[prefix++] = '/';
  }
  const std::size_t length = std::strlen(path);
  if (prefix + length >= sizeof absolute) return -1;
  std::memcpy(absolute + prefix, path, length + 1);
  for (int n = 0; n < kSlotCount; ++n) {
    int expected = kFree;
    if (!g_slots[n].state.compare_exchange_strong(expected, kFilling)) continue;
    std::memcpy(g_slots[n].path, absolute, prefix + length + 1);
    g_slots[n].isFolder = isFolder;
    g_slots[n].owner = ::getpid();
    g_slots[n].state.store(kLive, std::memory_order_release);
    return n;
  }
  return -1;
}

}  // namespace

int registerTempFile(const char* path) {
  return registerPath(path, false);
}

int registerTempFolder(const char* path) {
  return registerPath(path, true);
}

void unregisterTempFile(int slot) {
  if (slot < 0 || slot >= kSlotCount) return;
  // Live -> free. If the handler has taken the slot, the process is ending: leave it to the handler.
  int expected = kLive;
  g_slots[slot].state.compare_exchange_strong(expected, kFree);
}

int liveTempFileCount() {
  int count = 0;
  for (const Slot& slot : g_slots) count += slot.state.load() == kLive ? 1 : 0;
  return count;
}

}  // namespace sdfccd::detail

namespace sdfccd {

void installTempFileCleanupHandlers() {
  for (const int signalNumber : detail::kSignals) {
    struct sigaction previous {};
    if (::sigaction(signalNumber, nullptr, &previous) != 0) continue;
    const bool isDefault = !(previous.sa_flags & SA_SIGINFO) && previous.sa_handler == SIG_DFL;
    if (!isDefault) continue;  // ignored by the parent, or the program's own handler: leave it
    struct sigaction action {};
    action.sa_handler = detail::removeTempFilesAndReraise;
    sigemptyset(&action.sa_mask);
    for (const int other : detail::kSignals) sigaddset(&action.sa_mask, other);  // one cleanup at a time
    action.sa_flags = SA_RESTART;
    ::sigaction(signalNumber, &action, nullptr);
  }
}

}  // namespace sdfccd
