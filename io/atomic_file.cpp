#include "sdcb/io/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace sdcb {

Status WriteFileAtomically(const std::function<Status(std::ostream&)>& write,
                           const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    return IoError(path + ": is a directory; cannot write the output there");
  }
  static std::atomic<int> counter{0};
  const fs::path target(path);
  const std::string temp =
      (target.parent_path() /
       ("." + target.filename().string() + ".tmp." +
        std::to_string(::getpid()) + "." + std::to_string(counter++)))
          .string();
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
