#pragma once
// Private to optimizers/: Ctrl-C during minimize(). The SIGINT handler only sets a flag
// (nothing else is async-signal-safe); the Tracker polls it after every evaluation and
// iteration, and each back-end is then stopped through its own API.
#include <signal.h>  // struct sigaction

#include <csignal>

namespace tailor::detail {

// True once SIGINT arrived during the current minimize() call.
bool interrupt_received();

// Installs the handler for one minimize() call and restores the previous one afterwards. A
// pending interrupt from an enclosing minimize() (a functional that optimizes internally) is
// kept, and an interrupt received here is passed on to it: Ctrl-C means "stop everything".
class SigintGuard {
 public:
  SigintGuard();
  ~SigintGuard();
  SigintGuard(const SigintGuard&) = delete;
  SigintGuard& operator=(const SigintGuard&) = delete;

 private:
  std::sig_atomic_t outer_flag_;
  struct sigaction previous_ {};
  bool installed_ = false;
};

}  // namespace tailor::detail
