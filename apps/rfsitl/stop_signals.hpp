#pragma once
/// The signals that stop a command (SIGINT, SIGTERM), taken synchronously.
#include <pthread.h>
#include <signal.h>

namespace rfsitl::app {

/// Blocks SIGINT and SIGTERM in the calling thread, and so in every thread it
/// starts afterwards (they inherit the mask), and returns that set for
/// sigtimedwait: the caller takes them between polls, no handler runs.
inline sigset_t block_stop_signals() {
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  return signals;
}

}  // namespace rfsitl::app
