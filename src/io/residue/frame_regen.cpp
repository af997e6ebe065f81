// The writer's frame files a residue is computed against (pcd_residue.h PcdRegen; docs/FORMAT.md
// 14.3, "Lossless frame-file streams"): PCD frames by the PCD writer, PLY frames by the PLY
// writer, KITTI .bin frames by the .bin writer, each from a decoded frame block.
#include <cstring>

#include "capz/error.h"
#include "io/bin_folder.h"
#include "io/residue/pcd_residue.h"
#include "io/residue/pcd_residue_shared.h"

namespace capz {
namespace residue {

namespace {

using namespace pcdr;

const char* const kEncodings[3] = {"ascii", "binary", "binary_compressed"};
const char* const kPlyEncodings[3] = {"ascii", "binary_little_endian", "binary_big_endian"};

// Bytes through the line feed of the first line whose first word is `word` (the end when that
// line has none); SIZE_MAX without such a line.
size_t line_end_after(const uint8_t* p, size_t n, const char* word) {
  const size_t k = std::strlen(word);
  size_t pos = 0;
  while (pos < n) {
    const void* nl = std::memchr(p + pos, '\n', n - pos);
    const size_t e = nl ? static_cast<size_t>(static_cast<const uint8_t*>(nl) - p) : n;
    size_t w = pos;
    while (w < e && is_space(p[w])) ++w;
    if (e - w >= k && std::memcmp(p + w, word, k) == 0 && (e - w == k || is_space(p[w + k])))
      return e < n ? e + 1 : n;
    pos = e + 1;
  }
  return SIZE_MAX;
}

uint8_t kind_of(Format f) {
  return f == Format::kPLYFolder ? 5 : f == Format::kBinFolder ? 4 : kKind;
}

}  // namespace

size_t pcd_header_end(const uint8_t* p, size_t n) {
  return line_end_after(p, n, "DATA");
}

int pcd_encoding_code(const std::string& data) {
  for (int i = 0; i < 3; ++i)
    if (data == kEncodings[i]) return i;
  return 1;
}

PcdRegen::PcdRegen(const Take& header) : kind_(kind_of(header.format)) {
  for (int i = 0; i < 3; ++i) plans_[i] = pcd_frame_plan(header, kEncodings[i]);
  take_enc_ = pcd_encoding_code(header.pcd ? header.pcd->encoding : "binary");
  attrs_.resize(header.attributes.size());
  if (kind_ == 5) {
    for (int i = 0; i < 3; ++i) plies_[i] = ply_plan(header, kPlyEncodings[i]);
    // FORMAT.md "Lossless frame-file streams": the header of a frame of no vertices.
    PlyPlan own = ply_plan(header, header.ply ? header.ply->encoding : "");
    const std::vector<uint8_t> b = ply_frame_bytes(own, 0, nullptr, nullptr, attrs_);
    take_header_.assign(b.begin(), b.end());
  } else if (kind_ == 4) {
    record_ = bin_record_sources(header, bin_record_of(header));
  } else {
    take_header_ = pcd_frame_header(plans_[take_enc_].layout);  // before frame() sets a width
  }
}

std::string PcdRegen::take_header() const {
  return take_header_;
}

int PcdRegen::encodings() const {
  return kind_ == 4 ? 1 : 3;
}

size_t PcdRegen::header_end(const uint8_t* p, size_t n) const {
  return kind_ == 4 ? 0 : line_end_after(p, n, kind_ == 5 ? "end_header" : "DATA");
}

void PcdRegen::frame(const FrameBlock& b, size_t k, int enc, std::vector<uint8_t>* out,
                     size_t* header_end, LzfVariant lzf) {
  // A ragged block's frame k: its own count, from its offset (FORMAT.md "Lossless ragged
  // streams"); a fixed block's: b.points from k x b.points.
  const size_t N = b.frame_points(k), p0 = b.frame_begin(k), total = b.total_points();
  if (b.attributes.size() != attrs_.size() || k >= b.frames || enc < 0 || enc >= encodings())
    fail(ErrorCode::kInternal, "", "frame residue: a frame block without its point fields");
  for (size_t a = 0; a < attrs_.size(); ++a) {
    const size_t per_point = total ? b.attributes[a].size() / total : 0;
    if (b.attributes[a].size() != per_point * total)
      fail(ErrorCode::kInternal, "", "frame residue: a frame block without its point fields");
    attrs_[a] = b.attributes[a].data() + p0 * per_point;
  }
  const double* xyz = b.xyz.data() + p0 * 3;
  const uint8_t* valid = b.valid.data() + p0;
  if (kind_ == 4) {
    *out = bin_record_frame(record_, N, xyz, valid, attrs_);
    *header_end = 0;
    return;
  }
  // PCD frames, and the ascii columns a PLY ascii body is styled by (FORMAT.md 14.6).
  const int pcd_enc = kind_ == 5 ? 0 : enc;
  PcdFramePlan& plan = plans_[pcd_enc];
  // A frame of its own count (a ragged take's, or the one frame of a one-frame stream read
  // fixed): as wide as its points; a frame of the layout's count (a fixed take's, or one of a
  // stream of one organized shape, read fixed or as ragged frames): the layout's shape.
  if (kind_ == 5 || plan.layout.width * plan.layout.height != N) {
    plan.layout.width = N;
    plan.layout.height = 1;
  }
  if (kind_ == 3 || enc == 0) pcd_frame_points(plan, N, xyz, valid, attrs_, &points_);
  if (kind_ == 5) {
    *out = ply_frame_bytes(plies_[enc], N, xyz, valid, attrs_);
  } else {
    *out = pcd_frame_bytes(plan.layout, points_.data(), lzf);
  }
  *header_end = this->header_end(out->data(), out->size());
  if (*header_end == SIZE_MAX) fail(ErrorCode::kInternal, "", "the writer wrote no header end");
}

}  // namespace residue
}  // namespace capz
