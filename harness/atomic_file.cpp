// writeFileAtomically: an exclusive temporary beside the target, every write and the close checked, then
// a rename onto the target.
#include "atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <filesystem>
#include <system_error>

#include "robot_file.hpp"

namespace lowpair {

namespace fs = std::filesystem;

namespace {

std::atomic<unsigned long long> temporary_count{0};

// Longest part of the target's name kept in the temporary's (NAME_MAX is 255 on common file systems).
constexpr size_t kMaxTemporaryStem = 200;

std::string errorText(int error) { return std::generic_category().message(error); }

// Writes all of `content` to `fd`: 0, or the errno of the write that failed (ENOSPC, EFBIG, EIO, ...).
int writeAll(int fd, const std::string& content) {
  const char* data = content.data();
  size_t left = content.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, data, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    data += n;
    left -= static_cast<size_t>(n);
  }
  return 0;
}

}  // namespace

namespace {

// Writes `content` to an exclusive temporary beside `path`; returns the temporary's path.
// @throws RobotFileError (the temporary removed)
std::string writeTemporary(const std::string& path, const std::string& content) {
  auto failure = [&path](const std::string& reason) { return RobotFileError(path + ": cannot write: " + reason); };
  const fs::path target(path);
  if (path.empty() || !target.has_filename()) throw failure("not a file name");
  std::error_code ec;
  if (fs::is_directory(target, ec)) throw failure("is a directory");
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  const std::string stem = "." + target.filename().string().substr(0, kMaxTemporaryStem) + ".tmp-" +
                           std::to_string(::getpid()) + "-";

  // O_EXCL: never write into a file that is not ours (a leftover or another process's temporary)
  fs::path temporary;
  int fd = -1;
  for (int attempt = 0; fd < 0; ++attempt) {
    temporary = dir / (stem + std::to_string(temporary_count++));
    fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0 && (errno != EEXIST || attempt >= 100)) throw failure(errorText(errno));
  }
  int error = writeAll(fd, content);
  // close reports delayed write errors (NFS, quotas); its failure is a failure of the write
  if (::close(fd) != 0 && error == 0) error = errno;
  if (error == 0) return temporary.string();
  fs::remove(temporary, ec);
  throw failure(errorText(error));
}

}  // namespace

void writeFileAtomically(const std::string& path, const std::string& content) {
  StagedFiles files;
  files.stage(path, content);
  files.commit();
}

StagedFiles::~StagedFiles() {
  std::error_code ec;
  for (const Entry& e : entries_) fs::remove(e.temporary, ec);
}

void StagedFiles::stage(const std::string& path, const std::string& content) {
  entries_.reserve(entries_.size() + 1);  // the push_back below cannot throw once the temporary exists
  entries_.push_back(Entry{path, writeTemporary(path, content)});
}

void StagedFiles::commit() {
  while (!entries_.empty()) {
    const Entry& e = entries_.front();
    std::error_code ec;
    fs::rename(e.temporary, e.target, ec);
    if (ec) throw RobotFileError(e.target + ": cannot write: " + ec.message());  // the destructor cleans up
    entries_.erase(entries_.begin());
  }
}

}  // namespace lowpair
