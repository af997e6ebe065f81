// Decoder library (capz_decode): builds without PCL and without the transform encoders.
// Frame files (io/frame_files.h): folder listing, the fixed or ragged shape, the file-by-file
// frame source.
#include "io/frame_files.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <set>

#include "capz/error.h"
#include "capz/io.h"
#include "capz/tool/file.h"
#include "core/atomic_file.h"
#include "core/input_file.h"
#include "io/natural_sort.h"
#include "io/pcd_frame_writer.h"

namespace fs = std::filesystem;

namespace capz {

std::string FrameFiles::path(size_t f) const {
  return single && dir == "." ? names[f] : (fs::path(dir) / names[f]).string();
}

std::vector<uint8_t> read_file_head(const std::string& path, size_t bytes) {
  InputFile in(path);
  std::vector<uint8_t> head(static_cast<size_t>(std::min<uint64_t>(in.size(), bytes)));
  in.read_at(0, head.data(), head.size());
  return head;
}

std::vector<uint8_t> read_header_bytes(const std::string& path, const std::string& marker) {
  std::vector<uint8_t> head = read_file_head(path, size_t{16} << 10);
  if (head.size() == (size_t{16} << 10) &&
      std::string(head.begin(), head.end()).find(marker) == std::string::npos)
    head = read_file_head(path, (size_t{1} << 20) + 64);
  return head;
}

FrameView frame_view(const Take& take, size_t f) {
  FrameView v;
  const size_t b = take.frame_begin(f);
  v.points = take.frame_points(f);
  v.xyz = take.xyz.data() + b * 3;
  v.valid = take.valid.data() + b;
  for (const PointAttribute& a : take.attributes)
    v.attrs.push_back(a.data.data() + b * a.bytes_per_point());
  return v;
}

FrameView frame_view(const FrameBlock& b, size_t k) {
  FrameView v;
  const size_t p0 = b.frame_begin(k), total = b.total_points();
  v.points = b.frame_points(k);
  v.xyz = b.xyz.data() + p0 * 3;
  v.valid = b.valid.data() + p0;
  for (const std::vector<uint8_t>& a : b.attributes)
    v.attrs.push_back(a.data() + p0 * (total ? a.size() / total : 0));
  return v;
}

namespace {

// Refuses (kInvalidParameter, naming `path`) a take whose point field names a frame file cannot
// hold (point_field_fault): the files written would not read back.
void refuse_unreadable_names(const Take& take, const std::string& path) {
  const std::string fault = point_field_fault(take);
  if (!fault.empty())
    fail(ErrorCode::kInvalidParameter, path, fault + ": a frame file would not read back");
}

}  // namespace

void write_frame_files(const Take& take, const std::string& given, const std::string& ext,
                       bool overwrite, const FrameFileBytes& frame) {
  const std::string path = without_trailing_slashes(given);
  const std::string fault = take.shape_fault();
  if (!fault.empty()) fail(ErrorCode::kInternal, path, "take arrays: " + fault);
  refuse_unreadable_names(take, path);
  if (take.frames == 0) fail(ErrorCode::kUsage, path, "the take has no frames: nothing to write");
  if (single_frame_output(given, ext)) {
    if (take.frames != 1)
      fail(ErrorCode::kUsage, path,
           "a " + ext + " file holds one frame and the take has " + std::to_string(take.frames) +
               ": give a folder path");
    write_file(path, frame(frame_view(take, 0)), overwrite);
    return;
  }
  const std::vector<std::string> names = frame_output_names(take, ext);
  check_replaceable_frame_dir(path, ext, overwrite);
  AtomicDir out(path, overwrite, frames_go_beside);
  for (size_t f = 0; f < take.frames; ++f)
    write_file((fs::path(out.temp_dir()) / names[f]).string(), frame(frame_view(take, f)), true);
  out.commit();
}

namespace {

class FrameFolderSink : public FrameSink {
 public:
  FrameFolderSink(const Take& header, const std::string& path, const std::string& ext,
                  bool overwrite, bool needs_scan,
                  std::function<FrameFileBytes(std::optional<bool>)> make)
      : frames_(header.frames),
        path_(without_trailing_slashes(path)),
        single_(single_frame_output(path, ext)),
        overwrite_(overwrite),
        scan_(needs_scan),
        make_(std::move(make)) {
    if (frames_ == 0) fail(ErrorCode::kUsage, path, "the take has no frames: nothing to write");
    refuse_unreadable_names(header, path);
    if (single_) {  // as write_frame_files says it
      if (frames_ != 1)
        fail(ErrorCode::kUsage, path,
             "a " + ext + " file holds one frame and the take has " + std::to_string(frames_) +
                 ": give a folder path");
      return;
    }
    names_ = frame_output_names(header, ext);
    check_replaceable_frame_dir(path_, ext, overwrite);
    out_.reset(new AtomicDir(path_, overwrite, frames_go_beside));
  }
  bool wants_prescan() const override { return scan_ && !scanned_; }
  void prescan(const FrameBlock& b) override {
    xyz_float_ =
        xyz_float_ && coordinates_are_floats(b.total_points(), b.xyz.data(), b.valid.data());
  }
  // One file of one frame: its one block is all the prescan would see, so it is scanned as it
  // is written (not decoded twice).
  bool skip_prescan() override { return single_ && written_ == 0; }
  void write(const FrameBlock& b) override {
    const size_t total = b.total_points();
    if (b.first != written_ || written_ + b.frames > frames_ || b.xyz.size() != total * 3 ||
        b.valid.size() != total)
      fail(ErrorCode::kInternal, path_, "frames written out of order or beyond the header's count");
    if (!bytes_) {
      if (single_ && scan_) prescan(b);
      bytes_ = make_(scan_ ? std::optional<bool>(xyz_float_) : std::nullopt);
      scanned_ = true;
    }
    for (size_t k = 0; k < b.frames; ++k) {
      std::vector<uint8_t> file = bytes_(frame_view(b, k));
      if (single_)
        file_.swap(file);  // written at commit, as write_frame_files writes it
      else
        write_file((fs::path(out_->temp_dir()) / names_[b.first + k]).string(), file, true);
    }
    written_ += b.frames;
  }
  void commit() override {
    if (written_ != frames_)
      fail(ErrorCode::kInternal, path_,
           std::to_string(written_) + " of " + std::to_string(frames_) + " frames written");
    if (single_)
      write_file(path_, file_, overwrite_);
    else
      out_->commit();
  }

 private:
  size_t frames_, written_ = 0;
  std::string path_;
  bool single_, overwrite_, scan_, scanned_ = false, xyz_float_ = true;
  std::function<FrameFileBytes(std::optional<bool>)> make_;
  FrameFileBytes bytes_;
  std::vector<std::string> names_;
  std::unique_ptr<AtomicDir> out_;
  std::vector<uint8_t> file_;  // a single file's bytes until commit
};

}  // namespace

std::unique_ptr<FrameSink> frame_folder_sink(
    const Take& header, const std::string& path, const std::string& ext, bool overwrite,
    bool needs_scan, std::function<FrameFileBytes(std::optional<bool>)> make) {
  return std::unique_ptr<FrameSink>(
      new FrameFolderSink(header, path, ext, overwrite, needs_scan, std::move(make)));
}

bool has_extension(const std::string& path, const std::string& ext) {
  std::string e = fs::path(path).extension().string();
  for (auto& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e == ext;
}

bool hidden_name(const std::string& name) {
  return !name.empty() && name[0] == '.';
}

FrameFiles list_frame_files(const std::string& path, const std::string& ext) {
  FrameFiles ff;
  std::error_code ec;
  if (fs::is_regular_file(path, ec)) {
    const fs::path p(path);
    ff.dir = p.has_parent_path() ? p.parent_path().string() : ".";
    ff.names.push_back(p.filename().string());
    ff.single = true;
    return ff;
  }
  if (!fs::is_directory(path, ec)) fail(ErrorCode::kUsage, path, "not a directory");
  ff.dir = path;
  for (fs::directory_iterator it(path, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code ec2;
    const std::string name = it->path().filename().string();
    if (!hidden_name(name) && has_extension(name, ext) && fs::is_regular_file(it->path(), ec2))
      ff.names.push_back(name);
  }
  if (ec) fail(ErrorCode::kIo, path, "cannot list directory: " + ec.message());
  if (ff.names.empty()) fail(ErrorCode::kNotOurFormat, path, "no " + ext + " files in directory");
  std::sort(ff.names.begin(), ff.names.end(), natural_less);
  return ff;
}

const std::vector<std::string>* source_frame_names(const Take& take) {
  if (take.pcd && !take.pcd->frame_names.empty()) return &take.pcd->frame_names;
  if (take.ply && !take.ply->frame_names.empty()) return &take.ply->frame_names;
  if (take.bin && !take.bin->frame_names.empty()) return &take.bin->frame_names;
  return nullptr;
}

std::vector<std::string> frame_output_names(const Take& take, const std::string& ext) {
  const std::vector<std::string>* names = source_frame_names(take);
  std::vector<std::string> out;
  if (names && names->size() == take.frames) {
    std::set<std::string> seen;
    for (const std::string& n : *names) {
      // (A nuScenes sweep's name, NAME.pcd.bin, gives NAME.pcd, NAME.ply: its stem is NAME.)
      const bool nuscenes = ext != ".bin" && nuscenes_bin_name(n);
      const std::string name = has_extension(n, ext) ? n
                               : nuscenes ? fs::path(n).stem().replace_extension(ext).string()
                                          : fs::path(n).replace_extension(ext).string();
      if (n.empty() || name.find('/') != std::string::npos || name == ext ||
          fs::path(n).stem().string().empty() || n == "." || n == ".." || !seen.insert(name).second)
        break;
      out.push_back(name);
    }
    if (out.size() == take.frames) return out;
  }
  out.clear();
  for (size_t f = 0; f < take.frames; ++f) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "frame_%06zu", f + 1);
    out.push_back(buf + ext);
  }
  return out;
}

void check_replaceable_frame_dir(const std::string& dir, const std::string& ext, bool overwrite) {
  // Replacing an existing directory deletes it: only allow that for a folder of frame files.
  std::error_code ec;
  if (overwrite && fs::is_directory(dir, ec) && !frames_go_beside(dir)) {
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
      std::error_code ec2;
      if (!has_extension(it->path().string(), ext) || !fs::is_regular_file(it->symlink_status(ec2)))
        fail(ErrorCode::kUsage, dir,
             "refusing to replace this directory: it holds " + it->path().filename().string() +
                 ", which is not a " + ext + " frame");
    }
  }
}

bool single_frame_output(const std::string& path, const std::string& ext) {
  std::error_code ec;
  return !path.empty() && path.back() != '/' && has_extension(path, ext) &&
         !fs::is_directory(path, ec);
}

void set_frame_shape(const std::vector<size_t>& counts, Take* t) {
  t->frames = counts.size();
  const bool fixed =
      std::all_of(counts.begin(), counts.end(), [&](size_t c) { return c == counts[0]; });
  if (fixed) {
    t->points = counts.empty() ? 0 : counts[0];
    t->frame_offsets.clear();
  } else {
    t->points = 0;
    t->frame_offsets = offsets_of_counts(counts);
  }
  t->labels.clear();  // frame files carry no point labels (take.h)
}

void FileFrameSource::set_counts(const std::vector<size_t>& counts) {
  counts_ = counts;
  set_frame_shape(counts, &header_);
}

void FileFrameSource::read(size_t first, size_t count, FrameBlock* out) {
  read_frames(first, count, out, false);
}

void FileFrameSource::read_coordinates(size_t first, size_t count, FrameBlock* out) {
  read_frames(first, count, out, true);
}

void FileFrameSource::read_frames(size_t first, size_t count, FrameBlock* out, bool coordinates) {
  clip(&first, &count);
  if (header_.ragged())
    out->reset_ragged(first,
                      std::vector<size_t>(counts_.begin() + static_cast<long>(first),
                                          counts_.begin() + static_cast<long>(first + count)));
  else
    out->reset(first, count, header_.points, 0, false);
  const size_t A = coordinates ? 0 : header_.attributes.size();
  out->attributes.assign(A, std::vector<uint8_t>());
  for (size_t a = 0; a < A; ++a)
    out->attributes[a].reserve(out->total_points() * header_.attributes[a].bytes_per_point());
  // One frame's buffers, reused from frame to frame and freed at the end: not kept until the next
  // read (a one-frame take's whole cloud, while the encoder codes it).
  FrameData data;
  for (size_t k = 0; k < count; ++k) {
    const size_t f = first + k;
    if (coordinates)
      read_frame_coordinates(f, &data);
    else
      read_frame(f, &data);
    if (data.points != counts_[f] || data.xyz.size() != data.points * 3 ||
        data.valid.size() != data.points)
      fail(ErrorCode::kCorrupt, files_.path(f),
           "frame holds " + std::to_string(data.points) + " points, its header announced " +
               std::to_string(counts_[f]) + " (was the file changed while being read?)");
    const size_t b = out->frame_begin(k);
    std::copy(data.xyz.begin(), data.xyz.end(), out->xyz.begin() + static_cast<long>(b * 3));
    std::copy(data.valid.begin(), data.valid.end(), out->valid.begin() + static_cast<long>(b));
    if (data.attrs.size() != A) continue;  // fields left out of the header (drop_fields)
    for (size_t a = 0; a < A; ++a)
      out->attributes[a].insert(out->attributes[a].end(), data.attrs[a].begin(),
                                data.attrs[a].end());
  }
}

const char* frame_extension(Format f) {
  return f == Format::kPCDFolder   ? ".pcd"
         : f == Format::kPLYFolder ? ".ply"
         : f == Format::kBinFolder ? ".bin"
                                   : "";
}

}  // namespace capz
