// A real file system that fills up: a small tmpfs mounted on a test's directory when the
// tests run as root (CI does), so "disk full" is the kernel's ENOSPC, not a simulation.
// Without the privilege `mounted()` is false and the test says which path it took instead.
#pragma once

#include <fcntl.h>
#include <sys/mount.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <string>
#include <vector>

namespace leafdig::test {

class SmallFileSystem {
 public:
  SmallFileSystem(const std::filesystem::path& dir, std::size_t bytes) : dir_(dir) {
    std::filesystem::create_directories(dir_);
    const std::string options = "size=" + std::to_string(bytes) + ",mode=0777";
    mounted_ = ::geteuid() == 0 && ::mount("tmpfs", dir_.c_str(), "tmpfs", MS_NOSUID | MS_NODEV, options.c_str()) == 0;
  }
  SmallFileSystem(const SmallFileSystem&) = delete;
  SmallFileSystem& operator=(const SmallFileSystem&) = delete;
  ~SmallFileSystem() {
    if (mounted_) ::umount2(dir_.c_str(), MNT_DETACH);
  }
  [[nodiscard]] bool mounted() const { return mounted_; }
  [[nodiscard]] const std::filesystem::path& dir() const { return dir_; }

  // Writes a filler file until the file system refuses more (ENOSPC). Returns the errno
  // that stopped it.
  int fill() {
    const std::filesystem::path filler = dir_ / ".filler";
    const int fd = ::open(filler.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0600);
    if (fd < 0) return errno;
    const std::vector<char> block(4096, 'x');
    int err = 0;
    while (err == 0) {
      if (::write(fd, block.data(), block.size()) < 0) err = errno;
    }
    // Single bytes for what a block no longer fits in.
    while (::write(fd, block.data(), 1) == 1) {
    }
    ::close(fd);
    return err;
  }
  void release() { std::filesystem::remove(dir_ / ".filler"); }

 private:
  std::filesystem::path dir_;
  bool mounted_ = false;
};

}  // namespace leafdig::test
