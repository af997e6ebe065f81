// Decoder library (capz_decode): builds without PCL and without the transform encoders.
// A folder of PLY frames (or one .ply file) <-> Take (io/ply.h says what is read and written).
#include <filesystem>
#include <memory>

#include "capz/error.h"
#include "capz/io.h"
#include "capz/stream.h"
#include "capz/tool/file.h"
#include "io/frame_files.h"
#include "io/ply.h"

namespace capz {

namespace {

bool same_layout(const PlyHeader& a, const PlyHeader& b) {
  if (a.fields.size() != b.fields.size()) return false;
  for (size_t i = 0; i < a.fields.size(); ++i)
    if (a.fields[i].name != b.fields[i].name || a.fields[i].type != b.fields[i].type ||
        a.fields[i].size != b.fields[i].size)
      return false;
  return true;
}

// A frame file's header, checked against the file's size (the vertices it announces fit).
PlyHeader ply_head_of(const std::string& path) {
  const PlyHeader h = parse_ply_header(read_header_bytes(path, "end_header"), path);
  std::error_code ec;
  const uint64_t size = std::filesystem::file_size(path, ec);
  if (ec) fail(ErrorCode::kIo, path, "cannot read: " + ec.message());
  check_ply_body_fits(h, size, path);
  return h;
}

class PLYSource : public FileFrameSource {
 public:
  explicit PLYSource(const std::string& path) : FileFrameSource(list_frame_files(path, ".ply")) {
    std::vector<size_t> counts;
    for (size_t f = 0; f < files_.names.size(); ++f) {
      const std::string p = files_.path(f);
      const PlyHeader h = ply_head_of(p);
      if (f == 0) first_ = h;
      if (!same_layout(h, first_))
        fail(ErrorCode::kCorrupt, p,
             "frame has other vertex properties than the first frame (" + files_.names[0] + ")");
      counts.push_back(h.vertices);
    }
    set_counts(counts);
    header_.source = path;
    header_.format = Format::kPLYFolder;
    header_.units = "m";
    header_.units_assumed = true;
    auto extra = std::make_shared<PLYExtra>();
    extra->frame_names = files_.names;
    extra->encoding = first_.encoding;
    extra->version = first_.version;
    extra->fields = first_.fields;
    extra->type_names = first_.type_names;
    extra->comments = first_.comments;
    extra->obj_info = first_.obj_info;
    header_.ply = std::move(extra);
    for (const PCDField& f : first_.fields)
      if (f.name != "x" && f.name != "y" && f.name != "z")
        header_.attributes.push_back(attribute_of(f));
  }

 protected:
  void read_frame(size_t f, FrameData* out) override {
    const std::string p = files_.path(f);
    const std::vector<uint8_t> bytes = read_file(p);
    const PlyHeader h = parse_ply_header(bytes, p);
    if (!same_layout(h, first_))
      fail(ErrorCode::kCorrupt, p,
           "frame has other vertex properties than the first frame (" + files_.names[0] + ")");
    read_ply_frame(bytes, h, p, out);
  }

 private:
  PlyHeader first_;
};

}  // namespace

Take read_ply_folder(const std::string& path) {
  PLYSource source(path);
  return read_all_frames(source);
}

std::unique_ptr<FrameSource> open_ply_frames(const std::string& path) {
  return std::unique_ptr<FrameSource>(new PLYSource(path));
}

namespace {

const std::string& ply_encoding(const WriteOptions& opts, const std::string& path) {
  const std::string& enc = opts.ply_encoding;
  if (!enc.empty() && enc != "ascii" && enc != "binary_little_endian" && enc != "binary_big_endian")
    fail(ErrorCode::kInvalidParameter, path,
         "unknown PLY encoding '" + enc + "' (ascii, binary_little_endian or binary_big_endian)");
  return enc;
}

FrameFileBytes ply_file_writer(const Take& take, const std::string& enc,
                               std::optional<bool> xyz_float) {
  return [plan = ply_plan(take, enc, xyz_float)](const FrameView& v) {
    return ply_frame_bytes(plan, v.points, v.xyz, v.valid, v.attrs);
  };
}

}  // namespace

void write_ply_folder(const Take& take, const std::string& path, const WriteOptions& opts) {
  write_frame_files(take, path, ".ply", opts.overwrite,
                    ply_file_writer(take, ply_encoding(opts, path), std::nullopt));
}

std::unique_ptr<FrameSink> ply_folder_sink(const Take& header, const std::string& path,
                                           const WriteOptions& opts) {
  const std::string enc = ply_encoding(opts, path);
  return frame_folder_sink(header, path, ".ply", opts.overwrite,
                           ply_plan(header, enc).xyz_from_data,
                           [header, enc](std::optional<bool> xyz_float) {
                             return ply_file_writer(header, enc, xyz_float);
                           });
}

}  // namespace capz
