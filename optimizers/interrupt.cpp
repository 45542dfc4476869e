#include "optimizers/interrupt.hpp"

namespace tailor::detail {

namespace {

volatile std::sig_atomic_t g_interrupted = 0;
void on_sigint(int) { g_interrupted = 1; }

}  // namespace

bool interrupt_received() { return g_interrupted != 0; }

SigintGuard::SigintGuard() : outer_flag_(g_interrupted) {
  g_interrupted = 0;
  struct sigaction action {};
  action.sa_handler = on_sigint;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;  // a Ctrl-C must not make the solver's I/O fail with EINTR
  installed_ = sigaction(SIGINT, &action, &previous_) == 0;
}

SigintGuard::~SigintGuard() {
  if (installed_) sigaction(SIGINT, &previous_, nullptr);
  if (outer_flag_) g_interrupted = 1;
}

}  // namespace tailor::detail
