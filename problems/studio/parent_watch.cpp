#include "problems/studio/parent_watch.hpp"

#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <stdexcept>

namespace tailor::studio {

ParentWatch::ParentWatch(ParentWatchOptions options, std::function<void(const std::string&)> gone)
    : options_(options), gone_(std::move(gone)), parent_id_(static_cast<int>(getppid())) {
  if (options_.end_of_file_fd < 0 && !options_.parent) return;
  if (pipe(wake_) != 0) throw std::runtime_error("tailor studio: cannot create the parent watch's pipe");
  thread_ = std::thread([this] { run(); });
}

ParentWatch::~ParentWatch() {
  if (thread_.joinable()) {
    const char stop = 's';
    [[maybe_unused]] const auto written = write(wake_[1], &stop, 1);
    thread_.join();
  }
  for (const int fd : wake_)
    if (fd >= 0) close(fd);
}

void ParentWatch::run() {
  pollfd fds[2] = {{wake_[0], POLLIN, 0}, {options_.end_of_file_fd, POLLIN, 0}};
  const nfds_t count = options_.end_of_file_fd >= 0 ? 2 : 1;
  char buffer[4096];
  for (;;) {
    // Without the parent to watch, wait for the descriptor alone.
    const int ready = poll(fds, count, options_.parent ? options_.poll_ms : -1);
    if (ready < 0 && errno != EINTR) return gone_("the parent watch's poll failed");
    if (fds[0].revents) return;  // the destructor
    if (count == 2 && fds[1].revents) {
      // Data is read and dropped; end of file (or a hang-up, or an error) means the writer is gone.
      const ssize_t got = read(options_.end_of_file_fd, buffer, sizeof buffer);
      if (got == 0 || (got < 0 && errno != EINTR && errno != EAGAIN)) return gone_("its standard input was closed");
    }
    if (options_.parent && static_cast<int>(getppid()) != parent_id_) return gone_("its parent process ended");
  }
}

}  // namespace tailor::studio
