#include "forward/core/atomic_file.hpp"

#include <unistd.h>  // fsync, getpid

#include <atomic>
#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace tailor {

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
  // A name of this process and call: two writers of the same file never share a temporary.
  static std::atomic<unsigned> counter{0};
  temporary_ = path_ + ".tmp" + std::to_string(::getpid()) + "_" + std::to_string(counter.fetch_add(1));
  file_ = std::fopen(temporary_.c_str(), "wb");
  if (!file_) throw std::runtime_error("cannot write '" + path_ + "': " + std::strerror(errno));
}

AtomicFile::~AtomicFile() {
  if (!file_) return;
  std::fclose(file_);
  std::remove(temporary_.c_str());
}

void AtomicFile::write(const void* data, std::size_t size) {
  if (!file_) throw std::logic_error("AtomicFile: write after commit ('" + path_ + "')");
  if (error_ != 0 || size == 0) return;
  errno = 0;
  if (std::fwrite(data, 1, size, file_) != size) error_ = errno != 0 ? errno : EIO;
}

void AtomicFile::write(std::string_view bytes) { write(bytes.data(), bytes.size()); }

void AtomicFile::fail(int error) {
  std::remove(temporary_.c_str());
  throw std::runtime_error("cannot write '" + path_ + "': " + std::strerror(error));
}

void AtomicFile::commit() {
  if (!file_) throw std::logic_error("AtomicFile: committed twice ('" + path_ + "')");
  const auto check = [this](bool ok) {
    if (!ok && error_ == 0) error_ = errno != 0 ? errno : EIO;
  };
  errno = 0;
  check(std::fflush(file_) == 0);
  check(::fsync(fileno(file_)) == 0);
  check(std::fclose(file_) == 0);
  file_ = nullptr;
  if (error_ == 0) check(std::rename(temporary_.c_str(), path_.c_str()) == 0);
  if (error_ != 0) fail(error_);
}

void write_text_file_atomically(const std::string& path, std::string_view text) {
  AtomicFile file(path);
  file.write(text);
  file.commit();
}

}  // namespace tailor
