// Decoder library (capz_decode): builds without PCL and without the transform encoders.
// Format detection and dispatch to the per-format readers and writers.
//
// Input: a directory is a PCD folder; a file is recognised by its first bytes (C3D: byte 2 is
// 0x50, the parameter-section key; TRC: "PathFileType"; .capz: 0x89 "capz", see docs/FORMAT.md)
// and, when the bytes say nothing (empty or damaged files), by its extension, so that the format's
// own reader can name the fault. A .capz archive is not a take: read_take refuses it
// (kNotOurFormat) and points to `capz decompress`. Output: ".c3d" and ".trc" by extension; a path
// ending in '/', an existing directory or a name without extension is a PCD folder.
#include "capz/io.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "capz/error.h"
#include "core/atomic_file.h"

namespace fs = std::filesystem;

namespace capz {

namespace {

std::string lower_extension(const std::string& path) {
  std::string p = path;
  while (p.size() > 1 && p.back() == '/') p.pop_back();
  std::string ext = fs::path(p).extension().string();
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
  // C3D header word 1: byte 1 is 0x50 (the parameter-section key), byte 0 the parameter block.
  if (n >= 2 && static_cast<unsigned char>(head[1]) == 0x50 && head[0] != 0) return Format::kC3D;
  if (ext == ".capz") {
    *is_capz = true;
    return Format::kUnknown;
  }
  if (ext == ".c3d") return Format::kC3D;
  if (ext == ".trc") return Format::kTRC;
  return Format::kUnknown;
}

}  // namespace

Format detect_format(const std::string& path) {
  std::error_code ec;
  auto st = fs::status(path, ec);
  if (ec || !fs::exists(st)) fail(ErrorCode::kIo, path, "no such file or directory");
  if (fs::is_directory(st)) return Format::kPCDFolder;
  bool capz = false;
  return sniff(path, &capz);
}

Take read_take(const std::string& path) {
  std::error_code ec;
  auto st = fs::status(path, ec);
  if (ec || !fs::exists(st)) fail(ErrorCode::kIo, path, "no such file or directory");
  if (fs::is_directory(st)) return read_pcd_folder(path);
  bool capz = false;
  switch (sniff(path, &capz)) {
    case Format::kC3D:
      return read_c3d(path);
    case Format::kTRC:
      return read_trc(path);
    case Format::kPCDFolder:
      break;
    case Format::kUnknown:
      if (capz)
        fail(ErrorCode::kNotOurFormat, path,
             "is a .capz archive, not a take (use capz decompress or capz info)");
      break;
  }
  if (lower_extension(path) == ".pcd")
    fail(ErrorCode::kNotOurFormat, path,
         "a single PCD file is not a take: give the folder holding the frames");
  fail(ErrorCode::kNotOurFormat, path, "not a C3D or TRC file, nor a folder of PCD frames");
}

Format format_for_output(const std::string& path) {
  if (!path.empty() && path.back() == '/') return Format::kPCDFolder;
  std::error_code ec;
  if (fs::is_directory(path, ec)) return Format::kPCDFolder;
  const std::string ext = lower_extension(path);
  if (ext == ".c3d") return Format::kC3D;
  if (ext == ".trc") return Format::kTRC;
  if (ext.empty()) return Format::kPCDFolder;
  return Format::kUnknown;
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
  if (out == Format::kPCDFolder && take.rate > 0) {
    char rate[64];
    const std::to_chars_result r = std::to_chars(rate, rate + sizeof rate, take.rate);
    d.push_back("the frame rate (" + std::string(rate, r.ptr) + " Hz)");
  }
  return d;
}

void check_fields_fit(const Take& take, Format f, const std::string& path,
                      const WriteOptions& opts) {
  if (take.attributes.empty() || opts.drop_fields || f == Format::kPCDFolder) return;
  fail(ErrorCode::kUsage, path,
       std::string("a ") + (f == Format::kTRC ? "TRC" : "C3D") +
           " file cannot hold the point fields " + field_names(take) +
           ": write a PCD folder, or give --drop-fields to leave them out");
}

void write_take(const Take& take, const std::string& path, const WriteOptions& opts) {
  if (path.empty()) fail(ErrorCode::kUsage, path, "empty output path");
  const Format f = format_for_output(path);
  std::string target = path;
  while (target.size() > 1 && target.back() == '/') target.pop_back();
  check_fields_fit(take, f, target, opts);
  check_output_free(target, opts.overwrite);
  switch (f) {
    case Format::kC3D:
      write_c3d(take, target, opts);
      return;
    case Format::kTRC:
      write_trc(take, target, opts);
      return;
    case Format::kPCDFolder:
      write_pcd_folder(take, target, opts);
      return;
    case Format::kUnknown:
      break;
  }
  fail(ErrorCode::kUsage, path,
       "cannot tell the output format from the name: use .c3d, .trc, or a folder path "
       "(no extension or ending in '/') for PCD frames");
}

}  // namespace capz
