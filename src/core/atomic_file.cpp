// Decoder library (capz_decode): builds without PCL and without the transform encoders.
#include "core/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "capz/error.h"
#include "core/temporaries.h"

namespace fs = std::filesystem;

namespace capz {

static std::string sys_error() {
  return std::strerror(errno);
}

std::string without_trailing_slashes(std::string path) {
  while (path.size() > 1 && path.back() == '/') path.pop_back();
  return path;
}

void check_output_free(const std::string& path, bool overwrite,
                       bool (*takes_files)(const std::string& path)) {
  std::error_code ec;
  if (!overwrite && fs::exists(fs::symlink_status(path, ec)) && !(takes_files && takes_files(path)))
    fail(ErrorCode::kUsage, path, "output exists (use -f to overwrite)");
}

AtomicFile::AtomicFile(const std::string& path, bool overwrite)
    : path_(path), overwrite_(overwrite) {
  check_output_free(path, overwrite);
  tmp_ = temporaries::create([&] {
    std::string templ = path + ".tmp-XXXXXX";
    std::vector<char> buf(templ.begin(), templ.end());
    buf.push_back('\0');
    fd_ = mkstemp(buf.data());
    if (fd_ < 0) fail(ErrorCode::kIo, path, "cannot create temporary file: " + sys_error());
    return std::string(buf.data());
  });
  fchmod(fd_, 0644);
}

AtomicFile::~AtomicFile() {
  if (fd_ >= 0) ::close(fd_);
  if (!committed_ && !tmp_.empty()) temporaries::remove(tmp_);
}

void AtomicFile::write(const void* data, size_t size) {
  const char* p = static_cast<const char*>(data);
  while (size > 0) {
    ssize_t n = ::write(fd_, p, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0)
      fail(ErrorCode::kIo, path_,
           "write failed: " + (n < 0 ? sys_error() : std::string("no space")));
    p += n;
    size -= static_cast<size_t>(n);
  }
}

void AtomicFile::write_at(uint64_t offset, const void* data, size_t size) {
  const char* p = static_cast<const char*>(data);
  while (size > 0) {
    ssize_t n = ::pwrite(fd_, p, size, static_cast<off_t>(offset));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0)
      fail(ErrorCode::kIo, path_,
           "write failed: " + (n < 0 ? sys_error() : std::string("no space")));
    p += n;
    size -= static_cast<size_t>(n);
    offset += static_cast<uint64_t>(n);
  }
}

void AtomicFile::commit() {
  if (::fsync(fd_) != 0) fail(ErrorCode::kIo, path_, "fsync failed: " + sys_error());
  int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) fail(ErrorCode::kIo, path_, "close failed: " + sys_error());
  check_output_free(path_, overwrite_);
  temporaries::settle(tmp_, [&] {
    if (::rename(tmp_.c_str(), path_.c_str()) != 0)
      fail(ErrorCode::kIo, path_, "cannot rename temporary file into place: " + sys_error());
    return std::string();
  });
  committed_ = true;
}

AtomicDir::AtomicDir(const std::string& path, bool overwrite,
                     bool (*beside)(const std::string& path))
    : path_(without_trailing_slashes(path)), overwrite_(overwrite), beside_(beside) {
  check_output_free(path_, overwrite, beside_);
  tmp_ = temporaries::create_folder(path_ + ".tmp-XXXXXX", path_);
  // mkdtemp makes it 0700; a folder of frames is read by others as its files are (0644).
  ::chmod(tmp_.c_str(), 0755);
}

AtomicDir::~AtomicDir() {
  if (!committed_ && !tmp_.empty()) temporaries::remove(tmp_);
}

void AtomicDir::commit() {
  struct Appeared {};  // a folder taking the files beside its own appeared meanwhile
  const auto takes_files = [&] { return beside_ && beside_(path_); };
  if (!takes_files()) {
    check_output_free(path_, overwrite_);
    std::string old;
    try {
      // Both renames under the registry's lock: a signal's cleanup finds the new folder in place
      // and the old one registered, or the temporary registered and the old output where it was.
      temporaries::settle(tmp_, [&] {
        std::error_code ec;
        if (fs::exists(path_, ec)) {
          if (takes_files()) throw Appeared{};  // another job's subfolder made it (-r -T)
          check_output_free(path_, overwrite_);
          old = path_ + ".old-" + std::to_string(::getpid());
          fs::rename(path_, old, ec);
          if (ec)
            fail(ErrorCode::kIo, path_, "cannot move the existing output aside: " + ec.message());
        }
        fs::rename(tmp_, path_, ec);
        if (ec) {
          if (!old.empty()) fs::rename(old, path_, ec);
          if (old.empty() && takes_files()) throw Appeared{};
          fail(ErrorCode::kIo, path_, "cannot rename temporary directory into place");
        }
        return old;
      });
      committed_ = true;
      if (!old.empty()) temporaries::remove(old);
      return;
    } catch (const Appeared&) {
    }
  }
  move_in();
}

void AtomicDir::move_in() {
  std::vector<std::string> names;
  std::error_code ec;
  for (fs::directory_iterator it(tmp_, ec), end; !ec && it != end; it.increment(ec))
    names.push_back(it->path().filename().string());
  if (ec) fail(ErrorCode::kIo, tmp_, "cannot list: " + ec.message());
  for (const std::string& name : names)
    if (fs::exists(fs::symlink_status(path_ + "/" + name, ec)))
      fail(ErrorCode::kUsage, path_, "holds " + name + " already (not written over)");
  // Under the registry's lock, which a signal's cleanup waits for: every file moved in, or the
  // temporary folder whole and registered.
  temporaries::settle(tmp_, [&] {
    size_t moved = 0;
    for (; moved < names.size(); ++moved)
      if (::rename((tmp_ + "/" + names[moved]).c_str(), (path_ + "/" + names[moved]).c_str()) != 0)
        break;
    if (moved < names.size()) {  // the ones moved go back
      const std::string why = sys_error(), failed = names[moved];
      while (moved > 0) {
        --moved;
        ::rename((path_ + "/" + names[moved]).c_str(), (tmp_ + "/" + names[moved]).c_str());
      }
      fail(ErrorCode::kIo, path_, "cannot move " + failed + " into place: " + why);
    }
    ::rmdir(tmp_.c_str());
    return std::string();
  });
  committed_ = true;
}

std::vector<uint8_t> read_file(const std::string& path, uint64_t max_bytes) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) fail(ErrorCode::kUsage, path, "is a directory, expected a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(ErrorCode::kIo, path, "cannot open: " + sys_error());
  in.seekg(0, std::ios::end);
  std::streamoff size = in.tellg();
  if (size < 0) fail(ErrorCode::kIo, path, "cannot determine size");
  if (static_cast<uint64_t>(size) > max_bytes)
    fail(ErrorCode::kUsage, path, "file too large (" + std::to_string(size) + " bytes)");
  in.seekg(0, std::ios::beg);
  std::vector<uint8_t> data(static_cast<size_t>(size));
  if (size > 0 && !in.read(reinterpret_cast<char*>(data.data()), size))
    fail(ErrorCode::kIo, path, "read failed");
  return data;
}

void write_file(const std::string& path, const std::vector<uint8_t>& bytes, bool overwrite) {
  AtomicFile f(path, overwrite);
  f.write(bytes);
  f.commit();
}

}  // namespace capz
