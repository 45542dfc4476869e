#pragma once
// Ends `tailor studio` when whatever started it goes away (docs/studio.md, "Ending with its
// starter"): a notebook's kernel that dies, a shell that closes. Two signals, each opt-in:
//  - end of file on a descriptor (the program's stdin, a pipe whose writing end the starter holds:
//    the kernel closes it however it ends, SIGKILL included, so no signal handler is needed);
//  - the parent process id changing (the parent exited and the program was reparented), polled.
// Linux's PR_SET_PDEATHSIG is not used: it fires when the *thread* that forked exits, which a
// notebook's worker thread does long before the kernel.
#include <atomic>
#include <functional>
#include <string>
#include <thread>

namespace tailor::studio {

struct ParentWatchOptions {
  int end_of_file_fd = -1;  // a descriptor to read until end of file (0: stdin); -1: none
  bool parent = false;      // whether to watch the parent process id
  int poll_ms = 200;        // how often the parent id is compared (milliseconds)
};

// Runs a thread that calls `gone(reason)` once, from that thread, when a watched signal fires.
// The destructor stops the thread (without calling `gone`).
class ParentWatch {
 public:
  ParentWatch(ParentWatchOptions options, std::function<void(const std::string& reason)> gone);
  ~ParentWatch();
  ParentWatch(const ParentWatch&) = delete;
  ParentWatch& operator=(const ParentWatch&) = delete;

 private:
  void run();
  ParentWatchOptions options_;
  std::function<void(const std::string&)> gone_;
  int parent_id_ = 0;
  int wake_[2] = {-1, -1};  // a pipe that wakes the thread to stop
  std::thread thread_;
};

}  // namespace tailor::studio
