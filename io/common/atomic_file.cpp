#include "sdcb/io/common/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace sdcb {

namespace {

namespace fs = std::filesystem;

// A fresh temporary name for `path`: TemporaryFilePrefix + a counter.
std::string TemporaryPath(const std::string& path) {
  static std::atomic<int> counter{0};
  return TemporaryFilePrefix(path) + std::to_string(counter++);
}

}  // namespace

std::string TemporaryFilePrefix(const std::string& path) {
  return TemporaryFilePrefix(path, ::getpid());
}

std::string TemporaryFilePrefix(const std::string& path, int64_t pid) {
  const fs::path target(path);
  return (target.parent_path() / ("." + target.filename().string() + ".tmp." +
                                  std::to_string(pid) + "."))
      .string();
}

Status CheckWritableDestination(const std::string& path) {
  std::error_code ec;
  if (path.empty()) return IoError("an empty output path was given");
  if (fs::is_directory(path, ec)) {
    return IoError(path + ": is a directory; cannot write the output there");
  }
  const fs::path folder = fs::path(path).parent_path();
  if (!folder.empty() && !fs::is_directory(folder, ec)) {
    return IoError(path + ": the folder " + folder.string() +
                   " does not exist");
  }
  const std::string temp = TemporaryPath(path);
  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0644);
  if (fd < 0) {
    return IoError(path + ": cannot create the output file (" +
                   std::strerror(errno) + ")");
  }
  ::close(fd);
  ::unlink(temp.c_str());
  return Status::Ok();
}

Status WriteFileAtomically(const std::function<Status(std::ostream&)>& write,
                           const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    return IoError(path + ": is a directory; cannot write the output there");
  }
  const std::string temp = TemporaryPath(path);
  {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    if (!out) {
      return IoError(path + ": cannot create the output file (" +
                     std::strerror(errno) + ")");
    }
    const Status status = write(out);
    out.flush();
    const bool stream_ok = static_cast<bool>(out);
    out.close();
    if (!status.ok() || !stream_ok || out.fail()) {
      std::remove(temp.c_str());
      if (!status.ok()) return status;
      return IoError(path + ": writing the output failed (disk full?)");
    }
  }
  if (std::rename(temp.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    std::remove(temp.c_str());
    return IoError(path + ": cannot move the finished output into place (" +
                   reason + ")");
  }
  return Status::Ok();
}

Status WriteFileAtomically(const std::string& contents,
                           const std::string& path) {
  return WriteFileAtomically(
      [&](std::ostream& out) {
        out.write(contents.data(),
                  static_cast<std::streamsize>(contents.size()));
        return Status::Ok();
      },
      path);
}

}  // namespace sdcb
