#include "tools/interrupts.h"

#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <mutex>
#include <thread>
#include <vector>

#include "sdcb/io/common/atomic_file.h"

namespace sdcb::cli {
namespace {

// The registered outputs' temporary-file prefixes. Process-wide state, in
// the CLI only.
std::mutex g_mutex;
std::vector<std::string> g_prefixes;
bool g_run_ended = false;  // EndRunBeforeAnyInterrupt was called
// Set by the signal thread as soon as its wait returns, before it takes
// the lock: a signal it has taken is no longer pending.
std::atomic<bool> g_signal_taken{false};

sigset_t HandledSignals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGHUP);
  return set;
}

// Waits for a handled signal, cleans up, and ends the process by it. The
// lock is held until the process ends: a run that finishes meanwhile (its
// write failing because the temporary file is gone, say) cannot exit with
// its own status first (EndRunBeforeAnyInterrupt).
void WaitForInterrupt() {
  const sigset_t set = HandledSignals();
  int signal_number = 0;
  while (sigwait(&set, &signal_number) != 0) {
  }
  g_signal_taken.store(true);
  std::unique_lock<std::mutex> lock(g_mutex);
  if (g_run_ended) return;  // the run is complete: it ends as it would have
  for (const std::string& prefix : g_prefixes) RemoveFilesStartingWith(prefix);
  // Default action, delivered to this thread only: the process ends as if
  // it had never caught the signal (exit status 128 + N in shells).
  struct sigaction action = {};
  action.sa_handler = SIG_DFL;
  sigaction(signal_number, &action, nullptr);
  sigset_t one;
  sigemptyset(&one);
  sigaddset(&one, signal_number);
  pthread_sigmask(SIG_UNBLOCK, &one, nullptr);
  raise(signal_number);
  _exit(128 + signal_number);  // not reached
}

}  // namespace

void RemoveFilesStartingWith(const std::string& prefix) {
  namespace fs = std::filesystem;
  const fs::path p(prefix);
  const fs::path folder = p.parent_path().empty() ? "." : p.parent_path();
  const std::string name = p.filename().string();
  std::error_code ec;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end;
       it.increment(ec)) {
    if (it->path().filename().string().rfind(name, 0) == 0) {
      std::error_code ignored;
      fs::remove(it->path(), ignored);
    }
  }
}

void InstallInterruptCleanup() {
  const sigset_t set = HandledSignals();
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  std::thread(WaitForInterrupt).detach();
}

void EndRunBeforeAnyInterrupt() {
  // A signal sent while the run was still going ends the process by it,
  // even when the signal thread has not been scheduled yet (a loaded
  // machine): it is still pending then, or already taken.
  sigset_t pending;
  sigemptyset(&pending);
  sigpending(&pending);
  bool interrupted = g_signal_taken.load();
  for (int s : {SIGINT, SIGTERM, SIGHUP}) {
    interrupted = interrupted || sigismember(&pending, s) == 1;
  }
  if (interrupted) {
    for (;;) pause();  // the signal thread ends the process
  }
  std::lock_guard<std::mutex> lock(g_mutex);
  g_run_ended = true;
}

void RemoveTemporariesOnInterrupt(const std::string& output_path) {
  std::lock_guard<std::mutex> lock(g_mutex);
  g_prefixes.push_back(TemporaryFilePrefix(output_path));
}

}  // namespace sdcb::cli
