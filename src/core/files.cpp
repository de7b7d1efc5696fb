#include "proprio/core/files.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <random>
#include <sstream>

#include "proprio/core/error.hpp"

namespace proprio::core {
namespace fs = std::filesystem;
namespace {

// The longest file name most file systems allow (NAME_MAX); temporary names are kept within it.
constexpr std::size_t kMaxNameBytes = 255;
// Room left for the temporary suffix ".tmp-PID-N-HEX" (at most 5 + 10 + 1 + 10 + 1 + 8), the
// ".old" of a replaced directory and the leading "." of a staging directory.
constexpr std::size_t kSuffixRoom = 48;

std::string unique_suffix() {
  // Unique among concurrent writers in this and other processes: pid, a counter, a random word.
  static std::atomic<unsigned> counter{0};
  std::random_device rd;
  std::ostringstream s;
  s << ".tmp-" << ::getpid() << "-" << counter++ << "-" << std::hex << rd();
  return s.str();
}

// The part of a file name that its temporaries start with: the name, cut so that the name plus
// the suffix fits kMaxNameBytes (a legal long name must stay writable).
std::string temp_stem(const fs::path& target) {
  std::string name = target.filename().string();
  if (name.size() + kSuffixRoom > kMaxNameBytes) name.resize(kMaxNameBytes - kSuffixRoom);
  return name;
}

// A file descriptor closed on scope exit.
class Fd {
 public:
  explicit Fd(int fd) : fd_(fd) {}
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  Fd(Fd&& o) noexcept : fd_(o.fd_) { o.fd_ = -1; }
  Fd& operator=(Fd&&) = delete;
  ~Fd() {
    if (fd_ >= 0) ::close(fd_);
  }
  [[nodiscard]] int get() const { return fd_; }

 private:
  int fd_;
};

// Opens `path` for reading without blocking (a FIFO without a writer would block open(2)) and
// refuses anything but a regular file: FIFOs, devices and sockets can block or never end.
Fd open_regular(const fs::path& path, struct stat& st) {
  Fd fd(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY));
  if (fd.get() < 0) {
    if (errno == ENOENT) throw Error::in_file(path, "no such file");
    throw Error::in_file(path, std::string("cannot open: ") + std::strerror(errno));
  }
  if (::fstat(fd.get(), &st) != 0) {
    throw Error::in_file(path, std::string("cannot open: ") + std::strerror(errno));
  }
  if (S_ISDIR(st.st_mode)) throw Error::in_file(path, "is a directory, expected a file");
  if (!S_ISREG(st.st_mode)) {
    throw Error::in_file(path, "is not a regular file (a FIFO, device or socket)");
  }
  return fd;
}

// Up to `limit` bytes from `fd`; stops early at the end of the file.
std::string read_up_to(const Fd& fd, const fs::path& path, std::uintmax_t limit,
                       std::uintmax_t expected) {
  std::string out;
  out.resize(static_cast<std::size_t>(std::min(limit, expected)));
  std::size_t have = 0;
  for (;;) {
    if (have == out.size()) {
      if (have >= limit) break;
      // The file grew since fstat: read on in steps, never past `limit`.
      out.resize(static_cast<std::size_t>(std::min<std::uintmax_t>(limit, have + 65536)));
    }
    const ssize_t n = ::read(fd.get(), out.data() + have, out.size() - have);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw Error::in_file(path, std::string("read failed: ") + std::strerror(errno));
    }
    if (n == 0) break;
    have += static_cast<std::size_t>(n);
  }
  out.resize(have);
  return out;
}

bool process_gone(long pid) {
  return pid > 0 && pid != ::getpid() && ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH;
}

// Whether `a` is `b` or lies under it, component by component.
bool is_within(const fs::path& a, const fs::path& b) {
  auto ai = a.begin();
  for (auto bi = b.begin(); bi != b.end(); ++bi, ++ai) {
    if (bi->empty() && std::next(bi) == b.end()) break;  // "dir/" ends in an empty component
    if (ai == a.end() || *ai != *bi) return false;
  }
  return true;
}

}  // namespace

std::string read_file(const fs::path& path, std::uintmax_t max_bytes) {
  struct stat st {};
  const Fd fd = open_regular(path, st);
  const auto size = static_cast<std::uintmax_t>(st.st_size);
  if (size > max_bytes) {
    throw Error::in_file(path, "is " + std::to_string(size) + " bytes, more than the " +
                                   std::to_string(max_bytes) + " this file may have");
  }
  std::string out = read_up_to(fd, path, max_bytes + 1, size);
  if (out.size() > max_bytes) {
    throw Error::in_file(path, "grew past the " + std::to_string(max_bytes) +
                                   " bytes this file may have while it was read");
  }
  return out;
}

std::string read_file_head(const fs::path& path, std::size_t n) {
  struct stat st {};
  const Fd fd = open_regular(path, st);
  return read_up_to(fd, path, n, static_cast<std::uintmax_t>(st.st_size));
}

std::uintmax_t regular_file_size(const fs::path& path) {
  struct stat st {};
  const Fd fd = open_regular(path, st);
  return static_cast<std::uintmax_t>(st.st_size);
}

int remove_stale_temporaries(const fs::path& path) {
  fs::path target = path;
  if (target.filename().empty()) target = target.parent_path();
  const fs::path parent = target.has_parent_path() ? target.parent_path() : fs::path(".");
  const std::string stem = temp_stem(target) + ".tmp-";
  int removed = 0;
  std::error_code ec;
  for (fs::directory_iterator it(parent, ec), end; !ec && it != end; it.increment(ec)) {
    std::string name = it->path().filename().string();
    if (!name.empty() && name[0] == '.' && name.compare(1, stem.size(), stem) == 0) {
      name.erase(0, 1);  // a staging directory: "." + stem
    }
    if (name.compare(0, stem.size(), stem) != 0) continue;
    // ".tmp-PID-N-HEX": the writer's process id, then anything.
    const long pid = std::strtol(name.c_str() + stem.size(), nullptr, 10);
    if (!process_gone(pid)) continue;
    std::error_code rm;
    fs::remove_all(it->path(), rm);
    if (!rm) ++removed;
  }
  return removed;
}

void write_file_atomic(const fs::path& path, std::string_view contents) {
  std::error_code ec;
  if (path.has_parent_path()) fs::create_directories(path.parent_path(), ec);
  remove_stale_temporaries(path);
  const fs::path tmp = path.parent_path() / (temp_stem(path) + unique_suffix());
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw Error::in_file(path, std::string("cannot write: ") + std::strerror(errno));
  const char* p = contents.data();
  size_t left = contents.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      const std::string why = std::strerror(errno);
      ::close(fd);
      fs::remove(tmp, ec);
      throw Error::in_file(path, "write failed: " + why);
    }
    p += n;
    left -= static_cast<size_t>(n);
  }
  if (::fsync(fd) != 0 || ::close(fd) != 0) {
    fs::remove(tmp, ec);
    throw Error::in_file(path, std::string("write failed: ") + std::strerror(errno));
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw Error::in_file(path, "cannot rename temporary file into place: " + ec.message());
  }
}

void require_output_not_input(const fs::path& output, const std::vector<fs::path>& inputs,
                              std::string_view option) {
  if (output.empty()) return;
  std::error_code ec;
  const fs::path out = fs::weakly_canonical(fs::absolute(output, ec), ec);
  for (const fs::path& input : inputs) {
    if (input.empty()) continue;
    std::error_code ec2;
    const fs::path in = fs::weakly_canonical(fs::absolute(input, ec2), ec2);
    const bool same = out == in || (fs::exists(output, ec2) && fs::exists(input, ec2) &&
                                    fs::equivalent(output, input, ec2));
    if (same) {
      throw Error::in_file(output, std::string(option) + " is the same file as " + input.string() +
                                       ", which this run also reads or writes");
    }
    if (is_within(in, out)) {
      throw Error::in_file(output, std::string(option) + " holds the input " + input.string() +
                                       "; replacing it would delete that input");
    }
  }
}

StagedDirectory::StagedDirectory(fs::path final_path, bool overwrite,
                                 std::span<const std::string_view> markers)
    : final_(std::move(final_path)), overwrite_(overwrite) {
  std::error_code ec;
  if (final_.filename().empty()) final_ = final_.parent_path();  // "dir/" -> "dir"
  if (fs::exists(final_, ec)) {
    if (!fs::is_directory(final_, ec))
      throw Error::in_file(final_, "exists and is not a directory");
    if (!fs::is_empty(final_, ec)) {
      if (!overwrite_) {
        throw Error::in_file(final_, "exists and is not empty (pass --overwrite to replace it)");
      }
      const bool ours = std::any_of(markers.begin(), markers.end(), [&](std::string_view m) {
        std::error_code e;
        return fs::is_regular_file(final_ / m, e);
      });
      if (!ours) {
        std::string names;
        for (std::size_t i = 0; i < markers.size(); ++i) {
          if (i > 0) names += i + 1 == markers.size() ? " or " : ", ";
          names += markers[i];
        }
        std::string why = "exists and is not a directory proprio wrote (no ";
        why += names;
        why += "): not replacing it";
        throw Error::in_file(final_, why);
      }
    }
  }
  const fs::path parent = final_.has_parent_path() ? final_.parent_path() : fs::path(".");
  fs::create_directories(parent, ec);
  if (ec) throw Error::in_file(parent, "cannot create directory: " + ec.message());
  remove_stale_temporaries(final_);
  std::string name = ".";  // built in steps: GCC 12 warns falsely (-Wrestrict) on "." + string
  name += temp_stem(final_);
  name += unique_suffix();
  staging_ = parent / name;
  fs::create_directory(staging_, ec);
  if (ec) throw Error::in_file(staging_, "cannot create directory: " + ec.message());
}

StagedDirectory::~StagedDirectory() {
  if (!committed_) {
    std::error_code ec;
    fs::remove_all(staging_, ec);
  }
}

void StagedDirectory::commit() {
  std::error_code ec;
  if (fs::exists(final_, ec)) {
    // One atomic exchange: the path holds the old directory, then the new one, never nothing.
    if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, final_.c_str(), RENAME_EXCHANGE) == 0) {
      committed_ = true;
      fs::remove_all(staging_, ec);  // now the old directory
      return;
    }
    if (errno != EINVAL && errno != ENOSYS) {
      throw Error::in_file(final_, std::string("cannot replace: ") + std::strerror(errno));
    }
    // A file system without RENAME_EXCHANGE: move the old aside, then the new in.
    const fs::path old = final_.parent_path() / (temp_stem(final_) + unique_suffix() + ".old");
    fs::rename(final_, old, ec);
    if (ec) throw Error::in_file(final_, "cannot replace: " + ec.message());
    fs::rename(staging_, final_, ec);
    if (ec) {
      std::error_code ec2;
      fs::rename(old, final_, ec2);
      throw Error::in_file(final_, "cannot move result into place: " + ec.message());
    }
    fs::remove_all(old, ec);
  } else {
    fs::rename(staging_, final_, ec);
    if (ec) throw Error::in_file(final_, "cannot move result into place: " + ec.message());
  }
  committed_ = true;
}

}  // namespace proprio::core
