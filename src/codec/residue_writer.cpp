// The encoder's HASH and residue chunks (see residue_writer.h; layout in docs/FORMAT.md 7, 14).
#include "codec/residue_writer.h"

#include <cstring>
#include <filesystem>

#include "capz/error.h"
#include "capz/tool/file.h"
#include "coding/bytes.h"
#include "coding/container.h"
#include "coding/ply_types.h"
#include "io/frame_files.h"
#include "io/pcd_folder.h"

namespace capz {

namespace {

// The take's metadata as a decoder gets it from META (FORMAT.md "Frame-file sources"): a PLY
// take's vertex properties are META's layout, each with the type name the source spelled.
Take decoded_view(const Take& t) {
  Take v = t;  // a header: its frames come in blocks
  if (!t.ply || !t.pcd) return v;
  auto x = std::make_shared<PLYExtra>(*t.ply);
  x->fields = t.pcd->fields;
  x->type_names.clear();
  x->frame_names = t.pcd->frame_names;
  for (const PCDField& f : x->fields)
    x->type_names.push_back(spelled_ply_type(t.ply->fields, t.ply->type_names, f));
  v.ply = x;
  return v;
}

}  // namespace

std::string residue_original(const FrameSource& source, const CompressOptions& opts) {
  const bool fields_changed = opts.drop_fields || !opts.attr_error.empty();
  return fields_changed && !source.header().attributes.empty() ? std::string()
                                                               : source.original_file();
}

std::unique_ptr<ResidueWriter> ResidueWriter::open(const std::string& path, const Take& t,
                                                   bool check) {
  const Format f = t.format;
  const bool named = t.pcd && t.pcd->frame_names.size() == t.frames;
  const bool pcd = f == Format::kPCDFolder && named && pcd_output_names(t) == t.pcd->frame_names;
  // PLY and .bin frames (FORMAT.md "Lossless frame-file streams"): META's layout and names.
  const bool files = (f == Format::kPLYFolder || f == Format::kBinFolder) && named &&
                     frame_output_names(t, frame_extension(f)) == t.pcd->frame_names;
  if (path.empty() || (f != Format::kC3D && f != Format::kTRC && !pcd && !files)) return nullptr;
  return std::unique_ptr<ResidueWriter>(new ResidueWriter(path, t, check));
}

ResidueWriter::ResidueWriter(const std::string& path, const Take& header, bool check)
    : path_(path), header_(header), check_(check) {
  if (is_frame_files(header.format)) {
    pcd_ = true;  // hashed in file_chunks, when the stream turns out lossless
    return;
  }
  hash_ = hash128_file(path);
  if (header.format == Format::kC3D)
    c3d_.reset(new residue::C3DResidueEncoder(path));
  else
    trc_.reset(new residue::TRCResidueEncoder(path, header));
}

ResidueWriter::~ResidueWriter() = default;

void ResidueWriter::file_chunks(std::vector<uint8_t>* buf, bool exact) {
  exact_ = exact;
  check_ = check_ && exact;
  if (pcd_) {
    if (exact) pcd_file_chunks(buf);
    return;
  }
  const size_t before = buf->size();
  orig_.reset(new InputFile(path_));
  size_ = orig_->size();
  ByteWriter h;
  h.u64(size_);
  for (uint8_t b : hash_) h.u8(b);
  append_chunk(buf, "HASH", h.buffer());
  static const std::vector<C3DGroup> kNone;
  const std::vector<C3DGroup>& groups = header_.c3d ? header_.c3d->groups : kNone;
  file_part_ = c3d_ ? c3d_->file_part(groups) : trc_->file_part();
  append_chunk(buf, c3d_ ? "C3DR" : "TRCR", file_part_);
  file_bytes_ = buf->size() - before;
  bytes_ += file_bytes_;
  if (!check_) return;
  const std::string what = header_.source + " (self-check)";
  std::vector<uint8_t> head;
  if (c3d_) {
    c3d_back_.reset(
        new residue::C3DResidueDecoder(file_part_.data(), file_part_.size(), groups, what, size_));
    head = c3d_back_->head();
  } else {
    trc_back_.reset(
        new residue::TRCResidueDecoder(file_part_.data(), file_part_.size(), header_, what, size_));
    head = trc_back_->head();
  }
  check_bytes(0, head);
}

void ResidueWriter::window_chunk(size_t w, const FrameBlock& block, const FrameBlock* back,
                                 std::vector<uint8_t>* buf) {
  if (pcd_) {
    if (exact_) pcd_window_chunk(w, block, back, buf);
    return;
  }
  const std::vector<uint8_t> payload =
      c3d_ ? c3d_->window(block, exact_) : trc_->window(block, exact_);
  const size_t before = buf->size();
  if (trc_ || !payload.empty()) {
    ByteWriter b;
    b.varint(w);
    b.bytes(payload);
    append_chunk(buf, c3d_ ? "C3DP" : "TRCP", b.buffer());
  }
  bytes_ += buf->size() - before;
  if (!check_ || !back) return;
  std::vector<uint8_t> rebuilt;
  try {
    if (c3d_)
      c3d_back_->window(*back, payload.data(), payload.size(), &rebuilt);
    else
      trc_back_->window(*back, payload.data(), payload.size(), &rebuilt);
  } catch (const Error& e) {
    failed("window " + std::to_string(w) + ": the residue does not rebuild: " + e.what());
  }
  // The C3D encoder has just read the window's original bytes (exact: unamended).
  if (c3d_)
    check_bytes(w, rebuilt, c3d_->original(), c3d_->original_size(), c3d_->original_at());
  else
    check_bytes(w, rebuilt);
  if (c3d_ && c3d_->layout().rotations) check_rotations(w, *back, payload);
}

// The window's rotation bytes rebuilt from what the archive gives back, against the file's (the
// encoder's copy): the rotation section follows every frame, so it is compared here, out of the
// file's order, and counted, not hashed (every byte of the file is compared).
void ResidueWriter::check_rotations(size_t w, const FrameBlock& back,
                                    const std::vector<uint8_t>& payload) {
  std::vector<uint8_t> rebuilt;
  try {
    c3d_back_->rotation_window(back, payload.data(), payload.size(), &rebuilt);
  } catch (const Error& e) {
    failed("window " + std::to_string(w) + ": the rotations do not rebuild: " + e.what());
  }
  if (!rebuilt.empty() &&
      std::memcmp(rebuilt.data(), c3d_->original_rotations(), rebuilt.size()) != 0)
    failed("window " + std::to_string(w) + " rebuilds rotation bytes other than the original's");
  rotations_checked_ += rebuilt.size();
}

// The rebuilt bytes continue the original at rebuilt_: compares them and hashes them. The
// original's bytes are `known` when they are the same range, else read from the file.
void ResidueWriter::check_bytes(size_t w, const std::vector<uint8_t>& rebuilt, const uint8_t* known,
                                size_t known_size, uint64_t known_at) {
  if (rebuilt_ + rebuilt.size() > size_)
    failed("window " + std::to_string(w) + " rebuilds past the original's size");
  const uint8_t* orig = known;
  if (!known || known_at != rebuilt_ || known_size != rebuilt.size()) {
    orig_bytes_.resize(rebuilt.size());
    orig_->read_at(rebuilt_, orig_bytes_.data(), orig_bytes_.size());
    orig = orig_bytes_.data();
  }
  if (!rebuilt.empty() && std::memcmp(orig, rebuilt.data(), rebuilt.size()) != 0)
    failed("window " + std::to_string(w) + " rebuilds bytes other than the original's");
  rebuilt_hash_.update(rebuilt.data(), rebuilt.size());
  rebuilt_ += rebuilt.size();
}

void ResidueWriter::finish() {
  if (!check_) return;
  if (pcd_) {
    if (rebuilt_ != size_ || rebuilt_hash_.digest() != hash_)
      failed("the rebuilt frame files' size or hash differs from the originals'");
    return;
  }
  try {
    if (c3d_) {
      const residue::C3DFrameLayout& lay = c3d_back_->layout();
      if (lay.rotations) {
        check_bytes(0, c3d_back_->gap());
        if (rotations_checked_ != lay.rotation_bytes())
          failed("the rotation section was not rebuilt whole");
        rebuilt_ += rotations_checked_;
      }
      const std::vector<uint8_t> tail = c3d_back_->tail();
      check_bytes(0, tail);
    } else {
      trc_back_->finish();
    }
  } catch (const Error& e) {
    failed(std::string("the residue does not rebuild: ") + e.what());
  }
  // With a rotation section every byte was compared, the rotations out of order (not hashed).
  const bool hashed = !c3d_ || !c3d_back_->layout().rotations;
  if (rebuilt_ != size_ || (hashed && rebuilt_hash_.digest() != hash_))
    failed("the rebuilt file's size or hash differs from the original's");
}

// HASH over the frame files (each read and hashed once here: the chunk precedes the windows)
// and PCDR.
void ResidueWriter::pcd_file_chunks(std::vector<uint8_t>* buf) {
  const size_t before = buf->size();
  names_ = header_.pcd->frame_names;
  Hasher all;
  std::vector<uint8_t> first;
  for (size_t f = 0; f < names_.size(); ++f) {
    std::vector<uint8_t> b = read_file((std::filesystem::path(path_) / names_[f]).string());
    all.update(b.data(), b.size());
    sizes_.push_back(b.size());
    hashes_.push_back(hash128(b.data(), b.size()));
    size_ += b.size();
    if (f == 0) first = std::move(b);
  }
  hash_ = all.digest();
  ByteWriter h;
  h.u64(size_);
  for (uint8_t b : hash_) h.u8(b);
  append_chunk(buf, "HASH", h.buffer());
  const Take view = decoded_view(header_);
  pcd_enc_.reset(new residue::PCDResidueEncoder(view));
  file_part_ = pcd_enc_->file_part(first);
  append_chunk(buf, "PCDR", file_part_);
  file_bytes_ = buf->size() - before;
  bytes_ += file_bytes_;
  if (check_)
    pcd_back_.reset(new residue::PCDResidueDecoder(file_part_.data(), file_part_.size(), view,
                                                   header_.source + " (self-check)"));
}

// PCDP: each frame file read again (it must not have changed since HASH) and described against
// the writer's bytes; with the check, rebuilt from the frames the archive gives back.
void ResidueWriter::pcd_window_chunk(size_t w, const FrameBlock& block, const FrameBlock* back,
                                     std::vector<uint8_t>* buf) {
  std::vector<std::vector<uint8_t>> orig(block.frames);
  ByteWriter payload;
  for (size_t k = 0; k < block.frames; ++k) {
    const size_t f = block.first + k;
    const std::string file = (std::filesystem::path(path_) / names_[f]).string();
    orig[k] = read_file(file);
    if (orig[k].size() != sizes_[f] || hash128(orig[k].data(), orig[k].size()) != hashes_[f])
      fail(ErrorCode::kIo, file, "the frame file changed while it was being compressed");
    pcd_enc_->frame(block, k, orig[k], hashes_[f], payload);
  }
  ByteWriter b;
  b.varint(w);
  b.bytes(payload.buffer());
  const size_t before = buf->size();
  append_chunk(buf, "PCDP", b.buffer());
  bytes_ += buf->size() - before;
  if (!check_ || !back) return;
  ByteReader in(payload.buffer().data(), payload.size(), header_.source + " (self-check): PCDP");
  std::vector<uint8_t> rebuilt;
  for (size_t k = 0; k < block.frames; ++k) {
    const std::string& name = names_[block.first + k];
    try {
      pcd_back_->frame(*back, k, in, name, &rebuilt);
    } catch (const Error& e) {
      failed("frame file " + name + " does not rebuild: " + e.what());
    }
    if (rebuilt != orig[k]) failed("frame file " + name + " rebuilds other bytes");
    rebuilt_hash_.update(rebuilt.data(), rebuilt.size());
    rebuilt_ += rebuilt.size();
  }
}

void ResidueWriter::failed(const std::string& what) const {
  fail(ErrorCode::kInternal, header_.source,
       "self-check of the byte-exact residue failed: " + what +
           " (please report this; --no-check skips the check)");
}

}  // namespace capz
