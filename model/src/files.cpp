#include "leafdig/model/files.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>

#include "leafdig/model/errors.hpp"

namespace leafdig::model {

namespace {

[[noreturn]] void fail(const std::string& what, const std::filesystem::path& path, int error) {
  throw IoError(what + " " + path.string() + ": " + std::strerror(error));
}

// The inputs of this process, by device and inode, with the path each was read as.
struct Inputs {
  std::mutex lock;
  std::map<std::pair<dev_t, ino_t>, std::string> files;
};
Inputs& inputs() {
  static Inputs* const all = new Inputs;  // never destroyed: writers may run during exit
  return *all;
}

}  // namespace

void noteInput(const std::filesystem::path& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return;
  Inputs& in = inputs();
  const std::lock_guard<std::mutex> hold(in.lock);
  in.files.emplace(std::make_pair(st.st_dev, st.st_ino), path.string());
}

void writeFileAtomically(const std::filesystem::path& path, std::string_view bytes) {
  struct stat target {};
  if (::stat(path.c_str(), &target) == 0) {
    if (!S_ISREG(target.st_mode))
      throw InputError(path.string() + " is not a regular file (" +
                       (S_ISDIR(target.st_mode)    ? "a folder"
                        : S_ISFIFO(target.st_mode) ? "a named pipe"
                                                   : "a device") +
                       "): leafdig writes only files, and replaces none of these; give the path of a file");
    Inputs& in = inputs();
    const std::lock_guard<std::mutex> hold(in.lock);
    const auto read = in.files.find({target.st_dev, target.st_ino});
    if (read != in.files.end())
      throw InputError(path.string() + " is " + (read->second == path.string() ? "" : read->second + ", ") +
                       "a file this command reads: writing it would destroy its input; give another output path "
                       "(nothing was written)");
  }
  std::filesystem::path dir = path.parent_path();
  if (dir.empty()) dir = ".";
  // Appended piecewise: GCC 12 at -O3 raises a false -Wrestrict on "." + std::string. mkostemp
  // fills the X's at random and creates the file with O_EXCL (never through a planted link).
  std::string tempName(1, '.');
  tempName.append(path.filename().string()).append(".tmp.XXXXXX");
  std::string temp = (dir / tempName).string();
  const int fd = ::mkostemp(temp.data(), O_CLOEXEC);
  if (fd < 0) fail("cannot create a temporary file beside", path, errno);
  // mkostemp makes it 0600; an export is readable by others as before.
  (void)::fchmod(fd, 0644);
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
  if (S_ISREG(st.st_mode)) noteInput(path);
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
