// Decoder library (capz_decode): builds without PCL and without the transform encoders.
// Format detection and dispatch to the per-format readers and writers.
//
// Input: a directory is a folder of frame files (PCD, PLY or .bin by the files it holds); a
// .pcd or .bin file is a one-frame take; other files are recognised by their first bytes (PLY:
// "ply"; C3D: byte 2 is
// 0x50, the parameter-section key; TRC: "PathFileType"; .capz: 0x89 "capz", see docs/FORMAT.md)
// and, when the bytes say nothing (empty or damaged files), by its extension, so that the format's
// own reader can name the fault. A .capz archive is not a take: read_take refuses it
// (kNotOurFormat) and points to `capz decompress`. Output: ".c3d" and ".trc" by extension; a path
// ending in '/', an existing directory or a name without extension is a folder of frames (PCD
// unless WriteOptions or the take's own format say PLY or .bin); ".pcd", ".ply" and ".bin" one
// frame file.
#include "capz/io.h"

#include <dirent.h>
#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "capz/error.h"
#include "capz/stream.h"
#include "coding/ply_types.h"
#include "core/atomic_file.h"
#include "io/bin_folder.h"
#include "io/frame_files.h"

namespace fs = std::filesystem;

namespace capz {

namespace {

Format frame_file_format(const std::string& ext) {
  if (ext == ".pcd") return Format::kPCDFolder;
  if (ext == ".ply") return Format::kPLYFolder;
  if (ext == ".bin") return Format::kBinFolder;
  return Format::kUnknown;
}

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(without_trailing_slashes(path)).extension().string();
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

bool starts_with_nocase(const char* data, size_t n, const char* prefix) {
  size_t k = std::strlen(prefix);
  if (n < k) return false;
  for (size_t i = 0; i < k; ++i)
    if (std::tolower(static_cast<unsigned char>(data[i])) !=
        std::tolower(static_cast<unsigned char>(prefix[i])))
      return false;
  return true;
}

// Sniffs the first bytes of a regular file. Throws kIo if it cannot be opened.
Format sniff(const std::string& path, bool* is_capz) {
  *is_capz = false;
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(ErrorCode::kIo, path, "cannot open: " + std::string(std::strerror(errno)));
  char head[24] = {};
  in.read(head, sizeof head);
  const size_t n = static_cast<size_t>(in.gcount());
  const std::string ext = lower_extension(path);
  // "\x89CAPZ" (format 1.x) or "\x89capz" (pre-release, which the decoder refuses).
  if (n >= 5 && static_cast<unsigned char>(head[0]) == 0x89 &&
      (std::memcmp(head + 1, "CAPZ", 4) == 0 || std::memcmp(head + 1, "capz", 4) == 0)) {
    *is_capz = true;
    return Format::kUnknown;
  }
  if (starts_with_nocase(head, n, "PathFileType") ||
      (n >= 3 && std::memcmp(head, "\xEF\xBB\xBF", 3) == 0 &&
       starts_with_nocase(head + 3, n - 3, "PathFileType")))
    return Format::kTRC;
  // Frame files without a magic of their own (a .bin frame is raw floats) go by the extension.
  if (ext == ".bin" || ext == ".pcd") return frame_file_format(ext);
  if (n >= 4 && std::memcmp(head, "ply", 3) == 0 && (head[3] == '\n' || head[3] == '\r'))
    return Format::kPLYFolder;
  // C3D header word 1: byte 1 is 0x50 (the parameter-section key), byte 0 the parameter block.
  if (n >= 2 && static_cast<unsigned char>(head[1]) == 0x50 && head[0] != 0) return Format::kC3D;
  if (ext == ".capz") {
    *is_capz = true;
    return Format::kUnknown;
  }
  if (ext == ".c3d") return Format::kC3D;
  if (ext == ".trc") return Format::kTRC;
  return frame_file_format(ext);
}

// The folder format of a directory: that of its frame files (hidden ones aside,
// frame_files.h); PCD when it holds none (the PCD reader then names the fault). Frame files of
// two formats are refused (kNotOurFormat), naming one of each: a folder is one sequence, and
// reading one format would leave the other's frames out of the take.
Format folder_format(const std::string& dir) {
  std::string first[3];  // a file of each format: PCD, PLY, .bin
  const Format formats[3] = {Format::kPCDFolder, Format::kPLYFolder, Format::kBinFolder};
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    const Format f = frame_file_format(lower_extension(name));
    for (int k = 0; k < 3; ++k)
      if (f == formats[k] && first[k].empty() && !hidden_name(name)) first[k] = name;
  }
  std::vector<std::string> held;
  for (int k = 0; k < 3; ++k)
    if (!first[k].empty()) held.push_back(first[k]);
  if (held.size() > 1)
    fail(ErrorCode::kNotOurFormat, dir,
         "holds frame files of more than one format (" + held[0] + ", " + held[1] +
             "): a folder is one sequence of PCD, PLY or .bin frames; move the others to a "
             "folder of their own");
  for (int k = 0; k < 3; ++k)
    if (!first[k].empty()) return formats[k];
  return Format::kPCDFolder;
}

}  // namespace

bool holds_frame_files(const std::string& dir) {
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    std::error_code ec2;
    if (frame_file_format(lower_extension(name)) != Format::kUnknown && !hidden_name(name) &&
        it->is_regular_file(ec2))
      return true;
  }
  return false;
}

namespace {

// The type of directory entry `e` of folder `dir` as lstat(2) gives it (S_IFDIR, S_IFREG, ...):
// from readdir's d_type, a stat only where the file system leaves it unknown; 0 when it is gone.
mode_t entry_type(const std::string& dir, const dirent& e) {
#ifdef _DIRENT_HAVE_D_TYPE
  if (e.d_type != DT_UNKNOWN) return DTTOIF(e.d_type);
#endif
  struct stat st {};
  return ::lstat((dir + "/" + e.d_name).c_str(), &st) == 0 ? st.st_mode & S_IFMT : 0;
}

}  // namespace

// One readdir pass without a stat per entry: its callers ask again and again (the CLI's output
// check, the sink's, AtomicDir's and its commit's), and the folder may hold many archives.
bool frames_go_beside(const std::string& dir) {
  const std::string d = without_trailing_slashes(dir);
  struct stat st {};
  if (::lstat(d.c_str(), &st) != 0 || !S_ISDIR(st.st_mode)) return false;
  DIR* h = ::opendir(d.c_str());
  if (!h) return false;
  bool takes = true;
  errno = 0;
  for (const dirent* e; takes && (e = ::readdir(h)) != nullptr; errno = 0) {
    const std::string name = e->d_name;
    if (name == "." || name == ".." || hidden_name(name)) continue;
    const mode_t type = entry_type(d, *e);
    takes = type == S_IFDIR || (type == S_IFREG && lower_extension(name) == ".capz");
  }
  takes = takes && errno == 0;  // a listing that failed midway is not a folder that takes files
  ::closedir(h);
  return takes;
}

Format detect_format(const std::string& path) {
  std::error_code ec;
  auto st = fs::status(path, ec);
  if (ec || !fs::exists(st)) fail(ErrorCode::kIo, path, "no such file or directory");
  if (fs::is_directory(st)) return folder_format(path);
  bool capz = false;
  return sniff(path, &capz);
}

Take read_take(const std::string& path) {
  std::error_code ec;
  auto st = fs::status(path, ec);
  if (ec || !fs::exists(st)) fail(ErrorCode::kIo, path, "no such file or directory");
  bool capz = false;
  switch (fs::is_directory(st) ? folder_format(path) : sniff(path, &capz)) {
    case Format::kC3D:
      return read_c3d(path);
    case Format::kTRC:
      return read_trc(path);
    case Format::kPCDFolder:
      return read_pcd_folder(path);
    case Format::kPLYFolder:
      return read_ply_folder(path);
    case Format::kBinFolder:
      return read_bin_folder(path);
    case Format::kUnknown:
      if (capz)
        fail(ErrorCode::kNotOurFormat, path,
             "is a .capz archive, not a take (use capz decompress or capz info)");
      break;
  }
  fail(ErrorCode::kNotOurFormat, path,
       "not a C3D or TRC file, a PCD, PLY or .bin frame, nor a folder of them");
}

std::vector<PCDField> declared_bin_record(const std::string& path, const ReadOptions& opts) {
  if (opts.bin_fields.empty()) return {};
  std::vector<PCDField> record = parse_bin_record(opts.bin_fields, path);
  if (detect_format(path) != Format::kBinFolder)
    fail(ErrorCode::kUsage, path,
         "--bin-fields is for .bin frames, and this is not a .bin frame "
         "nor a folder of them");
  return record;
}

ReadOptions read_options_of(const Take& header) {
  ReadOptions r;
  if (header.bin && header.bin->declared) r.bin_fields = bin_record_text(header.bin->record);
  return r;
}

Take read_take(const std::string& path, const ReadOptions& opts) {
  if (opts.bin_fields.empty()) return read_take(path);
  const std::vector<PCDField> record = declared_bin_record(path, opts);
  return read_all_frames(*open_bin_frames(path, &record));
}

Format format_for_output(const std::string& path) {
  if (!path.empty() && path.back() == '/') return Format::kPCDFolder;
  std::error_code ec;
  if (fs::is_directory(path, ec)) return Format::kPCDFolder;
  const std::string ext = lower_extension(path);
  if (ext == ".c3d") return Format::kC3D;
  if (ext == ".trc") return Format::kTRC;
  if (ext.empty()) return Format::kPCDFolder;
  return frame_file_format(ext);
}

Format output_format(const Take& take, const std::string& path, const WriteOptions& opts) {
  const Format f = format_for_output(path);
  if (f != Format::kPCDFolder) return f;
  const std::string p = without_trailing_slashes(path);
  std::error_code ec;
  if (lower_extension(p) == ".pcd" && path.back() != '/' && !fs::is_directory(p, ec)) return f;
  if (is_frame_files(opts.folder_format)) return opts.folder_format;
  return is_frame_files(take.format) ? take.format : Format::kPCDFolder;
}

std::vector<std::string> dropped_by(const Take& take, Format out) {
  std::vector<std::string> d;
  if (out == Format::kC3D) return d;
  if (take.analog.channels > 0)
    d.push_back("the " + std::to_string(take.analog.channels) + " analog channels");
  if (take.c3d) {
    const size_t events = c3d_events(*take.c3d).size();
    d.push_back("the C3D parameter section" +
                (events ? " (with its " + std::to_string(events) + " events)" : std::string()));
  }
  if (take.rotations.segments > 0)
    d.push_back("the " + std::to_string(take.rotations.segments) + " rotation segments");
  if (out == Format::kBinFolder) {  // float32 x y z and the record's fields
    const std::vector<PCDField>* fields = take.file_fields();
    const std::vector<PCDField> record = bin_record_of(take);
    std::string wide;  // the 8-byte float fields a .bin frame rounds to float32
    const auto rounded = [&](const PCDField& f) {
      return std::any_of(record.begin(), record.end(), [&](const PCDField& r) {
        return r.name == f.name && r.type == 'F' && r.size == 4;
      });
    };
    if (fields)
      for (const PCDField& f : *fields)
        if (f.type == 'F' && f.size == 8 &&
            (f.name == "x" || f.name == "y" || f.name == "z" || rounded(f)))
          wide += (wide.empty() ? "" : " ") + f.name;
    if (!wide.empty()) d.push_back("float64 values (" + wide + ": rounded to float32)");
  }
  if (is_frame_files(out) && take.rate > 0) {
    char rate[64];
    const std::to_chars_result r = std::to_chars(rate, rate + sizeof rate, take.rate);
    d.push_back("the frame rate (" + std::string(rate, r.ptr) + " Hz)");
  }
  return d;
}

void check_fields_fit(const Take& take, Format f, const std::string& path,
                      const WriteOptions& opts) {
  if (take.ragged() && (f == Format::kC3D || f == Format::kTRC))
    fail(ErrorCode::kUsage, path,
         std::string("a ") + (f == Format::kTRC ? "TRC" : "C3D") +
             " file cannot hold frames of different point counts: write a PCD, PLY or .bin "
             "folder");
  if (opts.drop_fields || f == Format::kPCDFolder || f == Format::kUnknown) return;
  const std::vector<PCDField> record =
      f == Format::kBinFolder ? bin_output_record(take, path) : std::vector<PCDField>();
  const auto in_record = [&](const PointAttribute& a) {
    return std::any_of(record.begin(), record.end(),
                       [&](const PCDField& r) { return r.name == a.name; });
  };
  std::string unfit;  // the fields f cannot hold
  for (const PointAttribute& a : take.attributes) {
    // PLY has no 8-byte integers (ply_type_name): such a field would be left out.
    const bool fits = a.name == "_" ||
                      (f == Format::kPLYFolder && a.count == 1 && ply_type_name(a.type, a.size)) ||
                      (f == Format::kBinFolder && a.count == 1 && in_record(a));
    if (!fits) unfit += (unfit.empty() ? "" : ", ") + a.name;
  }
  if (unfit.empty()) return;
  const std::string bin = ".bin frame (" + bin_record_text(record) + ")";
  const char* what = f == Format::kTRC   ? "TRC file"
                     : f == Format::kC3D ? "C3D file"
                     : f == Format::kPLYFolder
                         ? "PLY frame (one value a property, no 64-bit integers)"
                         : bin.c_str();
  fail(ErrorCode::kUsage, path,
       std::string("a ") + what + " cannot hold the point fields " + unfit +
           ": write a PCD folder, or give --drop-fields to leave them out");
}

void write_take(const Take& take, const std::string& path, const WriteOptions& opts) {
  if (path.empty()) fail(ErrorCode::kUsage, path, "empty output path");
  const Format f = output_format(take, path, opts);
  const std::string target = without_trailing_slashes(path);
  check_fields_fit(take, f, target, opts);
  check_output_free(target, opts.overwrite, is_frame_files(f) ? frames_go_beside : nullptr);
  switch (f) {
    case Format::kC3D:
      write_c3d(take, target, opts);
      return;
    case Format::kTRC:
      write_trc(take, target, opts);
      return;
    case Format::kPCDFolder:
      write_pcd_folder(take, path, opts);  // its trailing '/' says a folder
      return;
    case Format::kPLYFolder:
      write_ply_folder(take, path, opts);  // its trailing '/' says a folder
      return;
    case Format::kBinFolder:
      write_bin_folder(take, path, opts);  // its trailing '/' says a folder
      return;
    case Format::kUnknown:
      break;
  }
  fail(ErrorCode::kUsage, path,
       "cannot tell the output format from the name: use .c3d, .trc, .pcd, .ply, .bin, or a "
       "folder path (no extension or ending in '/') for frame files");
}

}  // namespace capz
