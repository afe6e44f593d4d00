#pragma once
/// @file atomic_file.hpp
/// Writing an output file all or nothing: the content goes to a temporary file in the target's directory,
/// which is renamed onto the target only when every byte has been written and the file closed. A reader
/// sees the old file or the new one, never a partial one; a failure (full disk, missing directory, no
/// permission, the target is a directory) leaves the target as it was and removes the temporary. No fsync:
/// this protects against failed writes, not against a system crash.

#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

namespace lowpair::io {

/// Writes `content` to `path` atomically (see the file comment) when `path` is a regular file or a new
/// path. The temporary is `<dir>/.<name>.tmp-<pid>-<counter>`, created exclusively (mode 0666 minus the
/// umask). A symbolic link is followed to its end, whose file is replaced (the link stays a link). An
/// existing character device or FIFO (`/dev/null`, `/dev/full`, a named pipe) and a descriptor path
/// (`/dev/stdout`, `/dev/fd/N`, `/proc/self/fd/N`: written to the descriptor itself, after what was printed
/// to it) are written directly, never replaced: they are not all or nothing. Anything else (a directory, a socket, a block device) is refused.
/// @throws RobotFileError `PATH: cannot write: REASON`
void writeFileAtomically(const std::string& path, const std::string& content);

/// What writes an output's bytes to a stream, as they are made.
using StreamWriter = std::function<void(std::ostream&)>;

/// The same, the content written by `write` as it is made (in 64 KiB writes): an output of 10^6 rows is never
/// held whole in memory. An exception of `write` (an interruption, out of memory) leaves the target as it was
/// and removes the temporary (a device, FIFO or descriptor path, written directly, has what was written).
/// @throws RobotFileError `PATH: cannot write: REASON`, or what `write` throws
void writeFileAtomically(const std::string& path, const StreamWriter& write);

/// Several files all or nothing: each is written to its temporary when staged (a failure throws and
/// leaves every target as it was: the temporaries are removed by the destructor), and `commit()` renames
/// them onto their targets in order. Only a rename failing after the first has succeeded (the targets'
/// directory removed between two renames) can leave some targets replaced; commit names it.
class StagedFiles {
 public:
  StagedFiles() = default;
  StagedFiles(const StagedFiles&) = delete;
  StagedFiles& operator=(const StagedFiles&) = delete;
  ~StagedFiles();
  /// @throws RobotFileError `PATH: cannot write: REASON`
  void stage(const std::string& path, const std::string& content);
  /// @throws RobotFileError `PATH: cannot write: REASON`
  void commit();

 private:
  struct Entry {
    std::string target, temporary;  // no temporary: written directly by commit() (a device, FIFO, descriptor)
    std::string content;            // for a direct write only
    int descriptor = -1;            // this process's descriptor, for /dev/stdout and the like
    bool direct() const { return temporary.empty(); }
  };
  std::vector<Entry> entries_;
};

}  // namespace lowpair::io
