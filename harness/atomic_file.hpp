#pragma once
/// @file atomic_file.hpp
/// Writing an output file all or nothing: the content goes to a temporary file in the target's directory,
/// which is renamed onto the target only when every byte has been written and the file closed. A reader
/// sees the old file or the new one, never a partial one; a failure (full disk, missing directory, no
/// permission, the target is a directory) leaves the target as it was and removes the temporary. No fsync:
/// this protects against failed writes, not against a system crash.

#include <string>
#include <vector>

namespace lowpair {

/// Writes `content` to `path` atomically (see the file comment). The temporary is
/// `<dir>/.<name>.tmp-<pid>-<counter>`, created exclusively (mode 0666 minus the umask). An existing
/// `path` (a file or a symbolic link) is replaced, not written through.
/// @throws RobotFileError `PATH: cannot write: REASON`
void writeFileAtomically(const std::string& path, const std::string& content);

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
    std::string target, temporary;
  };
  std::vector<Entry> entries_;
};

}  // namespace lowpair
