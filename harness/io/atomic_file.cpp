// writeFileAtomically: an exclusive temporary beside the target, every write and the close checked, then
// a rename onto the target.
#include "io/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <ostream>
#include <streambuf>
#include <system_error>

#include "io/robot_file.hpp"

namespace lowpair::io {

namespace fs = std::filesystem;

namespace {

std::atomic<unsigned long long> temporary_count{0};

// Longest part of the target's name kept in the temporary's (NAME_MAX is 255 on common file systems).
constexpr size_t kMaxTemporaryStem = 200;

std::string errorText(int error) { return std::generic_category().message(error); }

// Writes `size` bytes at `data` to `fd`: 0, or the errno of the write that failed (ENOSPC, EFBIG, EIO, ...).
int writeAll(int fd, const char* data, size_t size) {
  size_t left = size;
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

int writeAll(int fd, const std::string& content) { return writeAll(fd, content.data(), content.size()); }

// A stream onto a descriptor in 64 KiB writes; the first failed write's errno is kept (later output is dropped).
class DescriptorBuffer : public std::streambuf {
 public:
  explicit DescriptorBuffer(int fd) : fd_(fd) { setp(buffer_.data(), buffer_.data() + buffer_.size()); }
  /// Writes what is buffered: 0, or the errno of the first write that failed.
  int finish() {
    drain();
    return error_;
  }

 protected:
  int_type overflow(int_type c) override {
    drain();
    if (error_ != 0) return traits_type::eof();
    if (!traits_type::eq_int_type(c, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(c);
      pbump(1);
    }
    return traits_type::not_eof(c);
  }
  int sync() override { return finish() == 0 ? 0 : -1; }

 private:
  void drain() {
    if (error_ == 0) error_ = writeAll(fd_, pbase(), static_cast<size_t>(pptr() - pbase()));
    setp(buffer_.data(), buffer_.data() + buffer_.size());
  }
  int fd_;
  int error_ = 0;
  std::array<char, 65536> buffer_{};
};

// What `write` puts on a stream, written to `fd`: 0, or the errno of the write that failed. An exception of
// `write` propagates (the caller removes what it made).
int writeStream(int fd, const StreamWriter& write) {
  DescriptorBuffer buffer(fd);
  std::ostream out(&buffer);
  write(out);
  return buffer.finish();
}

// How a file's bytes reach a descriptor: 0, or the errno of the write that failed.
using DescriptorWriter = std::function<int(int fd)>;

// Writes the content `write_to` writes to an exclusive temporary beside `path`; returns the temporary's path.
// @throws RobotFileError, or what write_to throws (the temporary removed)
std::string writeTemporary(const std::string& path, const DescriptorWriter& write_to) {
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
  // the replacement keeps the replaced file's permissions (a private file of mode 600 stayed 600 only by chance
  // of the umask before); a new file gets 0666 less the umask, as any program's
  struct stat existing {};
  int error = 0;
  if (::stat(path.c_str(), &existing) == 0 && S_ISREG(existing.st_mode) && ::fchmod(fd, existing.st_mode & 07777) != 0) {
    error = errno;
  }
  try {
    if (error == 0) error = write_to(fd);
  } catch (...) {  // (an interruption, out of memory): nothing replaced, nothing left behind
    ::close(fd);
    fs::remove(temporary, ec);
    throw;
  }
  // close reports delayed write errors (NFS, quotas); its failure is a failure of the write
  if (::close(fd) != 0 && error == 0) error = errno;
  if (error == 0) return temporary.string();
  fs::remove(temporary, ec);
  throw failure(errorText(error));
}

// Where an output path is written: `path` is the file to replace atomically, or, when `direct`, the
// device, FIFO or descriptor path to open and write.
struct OutputTarget {
  std::string path;
  bool direct = false;
  int descriptor = -1;  // this process's descriptor N for /dev/stdout, /dev/fd/N, /proc/self/fd/N
};

// N for this process's descriptor paths (/dev/stdin, /dev/stdout, /dev/stderr, /dev/fd/N,
// /proc/self/fd/N, /proc/<our pid>/fd/N), else -1.
int ownDescriptor(const std::string& path) {
  if (path == "/dev/stdout") return 1;
  if (path == "/dev/stderr") return 2;
  if (path == "/dev/stdin") return 0;
  for (const std::string& prefix :
       {std::string("/dev/fd/"), std::string("/proc/self/fd/"), "/proc/" + std::to_string(::getpid()) + "/fd/"}) {
    if (path.rfind(prefix, 0) != 0) continue;
    const std::string digits = path.substr(prefix.size());
    if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) return -1;
    return std::stoi(digits);
  }
  return -1;
}

// Longest chain of symbolic links followed (the kernel's own limit is 40).
constexpr int kMaxSymlinkHops = 40;

bool throughProc(const std::string& path) {
  return path.rfind("/proc/", 0) == 0 || path.rfind("/dev/fd/", 0) == 0 || path == "/dev/stdout" ||
         path == "/dev/stderr";
}

// Where and how `path` is written: the end of its chain of symbolic links (so a link to a regular file
// keeps being a link and its target is replaced), written atomically when that is a regular file or does
// not exist yet; written directly (opened, never replaced) when it is a character device, a FIFO or a
// descriptor path (/dev/stdout, /proc/self/fd/N: replacing what they resolve to would not reach the
// descriptor); refused otherwise.
// @throws RobotFileError `PATH: cannot write: REASON`
OutputTarget classifyOutput(const std::string& path) {
  auto failure = [&path](const std::string& reason) { return RobotFileError(path + ": cannot write: " + reason); };
  if (path.empty() || !fs::path(path).has_filename()) throw failure("not a file name");
  // follow the links to the file they end at, stopping at a descriptor path: its magic link ("pipe:[123]",
  // "/dev/pts/0") is not a path to rename onto
  bool descriptor = false;
  std::string end = path;
  for (int hop = 0;; ++hop) {
    if (throughProc(end)) {
      descriptor = true;
      break;
    }
    struct stat link {};
    if (::lstat(end.c_str(), &link) != 0 || !S_ISLNK(link.st_mode)) break;
    if (hop >= kMaxSymlinkHops) throw failure("too many levels of symbolic links");
    std::error_code ec;
    const fs::path next = fs::read_symlink(end, ec);
    if (ec) throw failure(ec.message());
    end = next.is_absolute() ? next.string() : (fs::path(end).parent_path() / next).string();
  }
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) {
    if (errno == ENOENT && !descriptor) return OutputTarget{end, false};  // a new file (or a dangling link's target)
    throw failure(errorText(errno));
  }
  if (S_ISDIR(info.st_mode)) throw failure("is a directory");
  const int own = descriptor ? ownDescriptor(end) : -1;
  if (S_ISCHR(info.st_mode) || S_ISFIFO(info.st_mode)) return OutputTarget{path, true, own};
  if (S_ISREG(info.st_mode)) return OutputTarget{descriptor ? path : end, descriptor, own};
  throw failure("not a regular file, a character device or a FIFO (a socket or a block device is not written)");
}

// Writes what `write_to` writes to this process's descriptor `own` when the path names one (after what was
// printed to it: the same file offset, as a shell redirection expects), else opens the existing character
// device, FIFO or another process's descriptor path (O_APPEND: a file behind it keeps what it holds).
// @throws RobotFileError `PATH: cannot write: REASON`
void writeDirectly(const std::string& path, int own, const DescriptorWriter& write_to) {
  if (own >= 0) {
    std::cout.flush();
    std::cerr.flush();
    std::fflush(nullptr);
    const int error = write_to(own);
    if (error != 0) throw RobotFileError(path + ": cannot write: " + errorText(error));
    return;
  }
  const int fd = ::open(path.c_str(), O_WRONLY | O_APPEND | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) throw RobotFileError(path + ": cannot write: " + errorText(errno));
  // the replacement keeps the replaced file's permissions (a private file of mode 600 stayed 600 only by chance
  // of the umask before); a new file gets 0666 less the umask, as any program's
  struct stat existing {};
  int error = 0;
  if (::stat(path.c_str(), &existing) == 0 && S_ISREG(existing.st_mode) && ::fchmod(fd, existing.st_mode & 07777) != 0) {
    error = errno;
  }
  try {
    if (error == 0) error = write_to(fd);
  } catch (...) {
    ::close(fd);
    throw;
  }
  if (::close(fd) != 0 && error == 0) error = errno;
  if (error != 0) throw RobotFileError(path + ": cannot write: " + errorText(error));
}

DescriptorWriter contentWriter(const std::string& content) {
  return [&content](int fd) { return writeAll(fd, content); };
}

}  // namespace

void writeFileAtomically(const std::string& path, const std::string& content) {
  StagedFiles files;
  files.stage(path, content);
  files.commit();
}

void writeFileAtomically(const std::string& path, const StreamWriter& write) {
  const OutputTarget target = classifyOutput(path);
  const DescriptorWriter write_to = [&write](int fd) { return writeStream(fd, write); };
  if (target.direct) {
    writeDirectly(target.path, target.descriptor, write_to);
    return;
  }
  const std::string temporary = writeTemporary(target.path, write_to);
  std::error_code ec;
  fs::rename(temporary, target.path, ec);
  if (ec) {
    const std::string reason = ec.message();
    fs::remove(temporary, ec);
    throw RobotFileError(target.path + ": cannot write: " + reason);
  }
}

StagedFiles::~StagedFiles() {
  std::error_code ec;
  for (const Entry& e : entries_) {
    if (!e.direct()) fs::remove(e.temporary, ec);
  }
}

void StagedFiles::stage(const std::string& path, const std::string& content) {
  entries_.reserve(entries_.size() + 1);  // the push_back below cannot throw once the temporary exists
  const OutputTarget target = classifyOutput(path);
  if (target.direct) {
    entries_.push_back(Entry{target.path, std::string(), content, target.descriptor});
  } else {
    entries_.push_back(Entry{target.path, writeTemporary(target.path, contentWriter(content)), std::string(), -1});
  }
}

void StagedFiles::commit() {
  while (!entries_.empty()) {
    const Entry& e = entries_.front();
    if (e.direct()) {
      writeDirectly(e.target, e.descriptor, contentWriter(e.content));
    } else {
      std::error_code ec;
      fs::rename(e.temporary, e.target, ec);
      if (ec) throw RobotFileError(e.target + ": cannot write: " + ec.message());  // the destructor cleans up
    }
    entries_.erase(entries_.begin());
  }
}

}  // namespace lowpair::io
