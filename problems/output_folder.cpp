#include "problems/output_folder.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <system_error>

#include "problems/scene_error.hpp"

namespace tailor {
namespace {

namespace fs = std::filesystem;

constexpr const char* kLockName = ".tailor.lock";

std::string now_text() {
  const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm utc{};
  gmtime_r(&t, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%d %H:%M:%S UTC", &utc);
  return text;
}

std::string read_all(int fd) {
  std::string text;
  char chunk[512];
  ::lseek(fd, 0, SEEK_SET);
  for (ssize_t n; (n = ::read(fd, chunk, sizeof chunk)) > 0;) text.append(chunk, static_cast<std::size_t>(n));
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  return text;
}

}  // namespace

OutputFolder::OutputFolder(std::string folder, const std::string& command) : folder_(std::move(folder)) {
  const std::string what = "output folder '" + folder_ + "'";
  std::error_code ec;
  if (fs::exists(folder_, ec) && !fs::is_directory(folder_, ec))
    throw SceneError(what + " is a file; --out needs a folder");
  if (!fs::exists(folder_, ec)) {
    created_ = fs::create_directories(folder_, ec);
    if (ec) throw SceneError("cannot create the " + what + ": " + ec.message());
  }
  const std::string lock = (fs::path(folder_) / kLockName).string();
  fd_ = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    const int error = errno;
    release_and_tidy();
    throw SceneError("cannot write in the " + what + ": " + std::strerror(error));
  }
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    const std::string holder = read_all(fd_);
    ::close(fd_);
    fd_ = -1;
    if (error == EWOULDBLOCK)
      throw SceneError("the " + what + " is in use by another run (" +
                       (holder.empty() ? std::string("holder unknown") : holder) +
                       "); wait for it to end or choose another --out");
    throw SceneError("cannot lock the " + what + ": " + std::strerror(error));
  }
  const std::string holder = "process " + std::to_string(::getpid()) + ", '" + command + "', since " + now_text();
  // The holder's description, for a second run's message. A failed write here means the folder
  // cannot take files (a full disk): say so now rather than after the solve.
  if (::ftruncate(fd_, 0) != 0 || ::write(fd_, holder.data(), holder.size()) != static_cast<ssize_t>(holder.size())) {
    const int error = errno;
    release_and_tidy();
    throw SceneError("cannot write in the " + what + ": " + std::strerror(error != 0 ? error : EIO));
  }
}

OutputFolder::~OutputFolder() {
  if (fd_ >= 0) ::close(fd_);  // closing releases the lock
}

void OutputFolder::release_and_tidy() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  if (!created_) return;
  std::error_code ec;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder_, ec))
    if (entry.path().filename() != kLockName) return;
  fs::remove_all(folder_, ec);
}

}  // namespace tailor
