// The studio's parent watch (problems/studio/parent_watch.hpp): end of file on a pipe (the
// starter's end closed) calls `gone` once, data on it does not, and a watch destroyed first
// never calls it. The parent-id signal is tested end to end (python/tests/test_studio.py, a
// killed shell), since the parent of this test cannot be made to end under it.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <string>
#include <thread>

#include "problems/studio/parent_watch.hpp"

namespace tailor::studio::parent_watch_test {

struct Pipe {
  int fd[2] = {-1, -1};
  Pipe() { EXPECT_EQ(pipe(fd), 0); }
  ~Pipe() {
    for (const int f : fd)
      if (f >= 0) close(f);
  }
  void close_writer() {
    close(fd[1]);
    fd[1] = -1;
  }
};

// Waits up to 2 s for `calls` to reach `n`.
bool reaches(const std::atomic<int>& calls, int n) {
  for (int i = 0; i < 200 && calls.load() < n; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  return calls.load() >= n;
}

TEST(StudioParentWatch, EndOfFileOnItsInputCallsGoneOnce) {
  Pipe input;
  std::atomic<int> calls{0};
  std::string reason;
  ParentWatchOptions options;
  options.end_of_file_fd = input.fd[0];
  ParentWatch watch(options, [&](const std::string& why) {
    reason = why;
    ++calls;
  });
  // Data from the starter is read and dropped: it does not count as the end.
  ASSERT_EQ(write(input.fd[1], "hello\n", 6), 6);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_EQ(calls.load(), 0);
  input.close_writer();
  ASSERT_TRUE(reaches(calls, 1)) << "end of file on the watched input was not noticed";
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_EQ(calls.load(), 1);
  EXPECT_NE(reason.find("standard input"), std::string::npos) << reason;
}

TEST(StudioParentWatch, ALiveParentAndAnOpenInputDoNotCallGone) {
  Pipe input;
  std::atomic<int> calls{0};
  {
    ParentWatchOptions options;
    options.end_of_file_fd = input.fd[0];
    options.parent = true;
    options.poll_ms = 10;
    ParentWatch watch(options, [&](const std::string&) { ++calls; });
    std::this_thread::sleep_for(std::chrono::milliseconds(150));
  }  // the destructor stops the thread without calling gone
  input.close_writer();
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_EQ(calls.load(), 0);
}

TEST(StudioParentWatch, NothingWatchedStartsNoThread) {
  std::atomic<int> calls{0};
  { ParentWatch watch(ParentWatchOptions{}, [&](const std::string&) { ++calls; }); }
  EXPECT_EQ(calls.load(), 0);
}

}  // namespace tailor::studio::parent_watch_test
