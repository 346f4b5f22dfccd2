// Whole-file output: a regular file is replaced in one rename, so readers see the old file or the
// new one and a failure leaves neither a part nor a truncated file; other outputs are written
// through.
#include "host/io/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "host/io/standard_output.h"

namespace dg::host {

namespace {

std::string reason(int error) {
  return error == ENOSPC ? "the disk is full" : error == EDQUOT ? "the disk quota is used up" : std::strerror(error);
}

// Writes every byte to fd; false (errno set) on failure.
bool write_all(int fd, const std::string& bytes) {
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      if (n == 0) errno = EIO;
      return false;
    }
    done += static_cast<size_t>(n);
  }
  return true;
}

// The file a path names: a symbolic link's target (followed to its end), else the path itself.
std::string resolved(const std::string& path) {
  struct stat link {};
  if (::lstat(path.c_str(), &link) != 0 || !S_ISLNK(link.st_mode)) return path;
  char target[PATH_MAX];
  if (::realpath(path.c_str(), target) != nullptr) return target;
  // A dangling link: write the file it names.
  std::string current = path;
  for (int hops = 0; hops < 40; ++hops) {
    std::vector<char> buffer(PATH_MAX);
    const ssize_t n = ::readlink(current.c_str(), buffer.data(), buffer.size() - 1);
    if (n < 0) return current;
    std::string next(buffer.data(), static_cast<size_t>(n));
    if (next.empty() || next[0] != '/') {
      const size_t slash = current.find_last_of('/');
      if (slash != std::string::npos) next = current.substr(0, slash + 1) + next;
    }
    current = next;
    struct stat again {};
    if (::lstat(current.c_str(), &again) != 0 || !S_ISLNK(again.st_mode)) return current;
  }
  throw std::runtime_error(path + ": too many levels of symbolic links");
}

}  // namespace

void write_file_atomically(const std::string& path, const std::string& bytes) {
  if (is_standard_output(path)) {
    if (!write_all(standard_output_fd(), bytes)) throw std::runtime_error("standard output: write failed: " + reason(errno));
    return;
  }
  const std::string target = resolved(path);
  struct stat existing {};
  const bool exists = ::stat(target.c_str(), &existing) == 0;
  if (exists && S_ISDIR(existing.st_mode)) throw std::runtime_error(path + ": is a directory");
  if (exists && !S_ISREG(existing.st_mode)) {
    // A device, a pipe or a socket: written through, never replaced by a regular file.
    const int fd = ::open(target.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd < 0) throw std::runtime_error(path + ": cannot open: " + reason(errno));
    const bool ok = write_all(fd, bytes);
    const int error = errno;
    ::close(fd);
    if (!ok) throw std::runtime_error(path + ": write failed: " + reason(error));
    return;
  }
  const size_t slash = target.find_last_of('/');
  const std::string directory = slash == std::string::npos ? "." : slash == 0 ? "/" : target.substr(0, slash);
  const std::string name = slash == std::string::npos ? target : target.substr(slash + 1);
  std::string pattern = directory + "/." + name + ".XXXXXX";
  std::vector<char> temporary(pattern.begin(), pattern.end());
  temporary.push_back('\0');
  const int fd = ::mkostemp(temporary.data(), O_CLOEXEC);
  if (fd < 0) throw std::runtime_error(path + ": cannot create a file in " + directory + ": " + reason(errno));
  // The new file keeps the old one's permissions; a new one gets the usual rw-r--r-- less the umask.
  mode_t mode = 0644;
  if (exists) {
    mode = existing.st_mode & 07777;
  } else {
    const mode_t mask = ::umask(0);
    ::umask(mask);
    mode &= ~mask;
  }
  bool ok = ::fchmod(fd, mode) == 0 && write_all(fd, bytes) && ::fsync(fd) == 0;
  int error = errno;
  if (::close(fd) != 0 && ok) {
    ok = false;
    error = errno;
  }
  if (ok && ::rename(temporary.data(), target.c_str()) != 0) {
    ok = false;
    error = errno;
  }
  if (!ok) {
    ::unlink(temporary.data());
    throw std::runtime_error(path + ": write failed: " + reason(error) + "; nothing was written");
  }
}

}  // namespace dg::host
