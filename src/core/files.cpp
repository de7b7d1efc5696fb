#include "proprio/core/files.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>

#include "proprio/core/error.hpp"

namespace proprio::core {
namespace fs = std::filesystem;
namespace {

std::string unique_suffix() {
  // Unique among concurrent writers in this and other processes: pid, a counter, a random word.
  static std::atomic<unsigned> counter{0};
  std::random_device rd;
  std::ostringstream s;
  s << ".tmp-" << ::getpid() << "-" << counter++ << "-" << std::hex << rd();
  return s.str();
}

}  // namespace

std::string read_file(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw Error::in_file(path, "no such file");
  if (fs::is_directory(path, ec)) throw Error::in_file(path, "is a directory, expected a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error::in_file(path, std::string("cannot open: ") + std::strerror(errno));
  std::ostringstream s;
  s << in.rdbuf();
  if (in.bad()) throw Error::in_file(path, "read failed");
  return s.str();
}

void write_file_atomic(const fs::path& path, std::string_view contents) {
  std::error_code ec;
  if (path.has_parent_path()) fs::create_directories(path.parent_path(), ec);
  const fs::path tmp = path.string() + unique_suffix();
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

StagedDirectory::StagedDirectory(fs::path final_path, bool overwrite)
    : final_(std::move(final_path)), overwrite_(overwrite) {
  std::error_code ec;
  if (final_.filename().empty()) final_ = final_.parent_path();  // "dir/" -> "dir"
  if (fs::exists(final_, ec)) {
    if (!fs::is_directory(final_, ec)) throw Error::in_file(final_, "exists and is not a directory");
    if (!overwrite_ && !fs::is_empty(final_, ec)) {
      throw Error::in_file(final_, "exists and is not empty (pass --force to replace it)");
    }
  }
  const fs::path parent = final_.has_parent_path() ? final_.parent_path() : fs::path(".");
  fs::create_directories(parent, ec);
  if (ec) throw Error::in_file(parent, "cannot create directory: " + ec.message());
  std::string name = ".";  // built in steps: GCC 12 warns falsely (-Wrestrict) on "." + string
  name += final_.filename().string();
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
    // An empty directory (or, with overwrite, an old result) is moved aside, then removed.
    const fs::path old = final_.string() + unique_suffix() + ".old";
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
