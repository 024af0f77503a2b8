#include "leafdig/model/files.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "leafdig/model/errors.hpp"

namespace leafdig::model {

namespace {

[[noreturn]] void fail(const std::string& what, const std::filesystem::path& path, int error) {
  throw IoError(what + " " + path.string() + ": " + std::strerror(error));
}

}  // namespace

void writeFileAtomically(const std::filesystem::path& path, std::string_view bytes) {
  std::filesystem::path dir = path.parent_path();
  if (dir.empty()) dir = ".";
  // Appended piecewise: GCC 12 at -O3 raises a false -Wrestrict on "." + std::string.
  std::string tempName(1, '.');
  tempName.append(path.filename().string()).append(".tmp.").append(std::to_string(::getpid()));
  const std::filesystem::path temp = dir / tempName;
  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) fail("cannot create", temp, errno);
  std::size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int error = n < 0 ? errno : ENOSPC;
      ::close(fd);
      ::unlink(temp.c_str());
      fail("cannot write", path, error);
    }
    written += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) {
    const int error = errno;
    ::close(fd);
    ::unlink(temp.c_str());
    fail("cannot flush", path, error);
  }
  if (::close(fd) != 0) {
    const int error = errno;
    ::unlink(temp.c_str());
    fail("cannot close", path, error);
  }
  if (::rename(temp.c_str(), path.c_str()) != 0) {
    const int error = errno;
    ::unlink(temp.c_str());
    fail("cannot rename the finished file to", path, error);
  }
}

std::string readFile(const std::filesystem::path& path, std::uintmax_t maxBytes) {
  // A device, a FIFO or a directory is not read at all (/dev/zero would never end, a FIFO
  // would block), and a file larger than any real one is refused before it is read.
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) fail("cannot open", path, errno);
  if (!S_ISREG(st.st_mode))
    throw InputError(path.string() + " is not a regular file (" +
                     (S_ISDIR(st.st_mode)    ? "a folder"
                      : S_ISFIFO(st.st_mode) ? "a named pipe"
                      : S_ISCHR(st.st_mode)  ? "a character device"
                      : S_ISBLK(st.st_mode)  ? "a block device"
                                             : "a socket") +
                     "): give the path of a file");
  const auto tooLarge = [&](std::uintmax_t bytes) {
    throw InputError(path.string() + " is " + std::to_string(bytes >> 20) + " MB; " +
                     "a file leafdig reads is at most " + std::to_string(maxBytes >> 20) +
                     " MB. Is this the right file?");
  };
  if (static_cast<std::uintmax_t>(st.st_size) > maxBytes) tooLarge(static_cast<std::uintmax_t>(st.st_size));
  std::ifstream in(path, std::ios::binary);
  if (!in) fail("cannot open", path, errno);
  std::string out;
  out.resize(static_cast<std::size_t>(st.st_size));
  in.read(out.data(), static_cast<std::streamsize>(out.size()));
  if (in.bad()) fail("cannot read", path, errno);
  out.resize(static_cast<std::size_t>(in.gcount()));
  // It may have grown since: read on, up to the bound.
  char buffer[65536];
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
    out.append(buffer, static_cast<std::size_t>(in.gcount()));
    if (out.size() > maxBytes) tooLarge(out.size());
  }
  if (in.bad()) fail("cannot read", path, errno);
  return out;
}

std::string lowerExtension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return ext;
}

}  // namespace leafdig::model
