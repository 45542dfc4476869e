#pragma once
// The output folder of a command-line verb, claimed before any work (problems/cli/run_cli.cpp):
// created when missing, checked for writing, and locked, so that a wrong --out fails at once
// instead of after the solve, and two runs never write into one folder.
//
// The lock is an advisory lock (flock) on DIR/.tailor.lock, which holds the holder's process id,
// command line and start time. The operating system releases it when the process ends, however
// it ends, so a killed run leaves no stale lock; the file itself stays (a later run reuses it).
#include <string>

namespace tailor {

class OutputFolder {
 public:
  // Claims `folder` for `command` (how the holder is named to a second run). Throws SceneError
  // (exit 2) naming the folder: a path that is a file, a folder that cannot be created or written
  // in, or one that another run holds (its process id, command line and start time).
  OutputFolder(std::string folder, const std::string& command);
  ~OutputFolder();  // releases the lock
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  const std::string& path() const { return folder_; }
  // Releases the lock; when this claim created the folder and nothing but the lock file is in it
  // (a run refused for bad input), removes the folder again.
  void release_and_tidy();

 private:
  std::string folder_;
  bool created_ = false;
  int fd_ = -1;
};

}  // namespace tailor
