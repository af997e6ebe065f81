// Fuzz target: the PCD residue (src/io/residue/pcd_residue.h, FORMAT.md 7.3, 14.3) of a small
// take of frame files (x y z float32 and an intensity field; frames 1..4 of 5 points, point 1 of
// frame 0 a gap): PCD frames, or PLY or .bin frames ("Lossless frame-file streams": PCDR kinds 5
// and 4). Byte 0 picks the mode, the frame count (bits 1-2), the PCD encoding (bits 3-4) and the
// frame format (bits 5-6: 0 PCD, 1 PLY, 2 .bin, 3 PCD):
//   mode even: then a varint n, n bytes of PCDR payload and the rest a PCDP payload (after its
//     window index); decoding every frame must return or throw capz::Error;
//   mode odd: the rest are edits of the frame files the writer gives (byte changes, insertions,
//     a header of its own, trailing bytes, by the bytes' values): the residue of the edited
//     files must decode to exactly them.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "capz/error.h"
#include "coding/bytes.h"
#include "core/hash.h"
#include "fuzz_common.h"
#include "io/residue/pcd_residue.h"

namespace {

capz::Take make_header(size_t frames, const char* encoding, int format) {
  capz::Take t;
  t.format = format == 1   ? capz::Format::kPLYFolder
             : format == 2 ? capz::Format::kBinFolder
                           : capz::Format::kPCDFolder;
  t.frames = frames;
  t.points = 5;
  auto x = std::make_shared<capz::PCDExtra>();
  x->encoding = format == 1 || format == 2 ? "binary" : encoding;
  for (const char* n : {"x", "y", "z", "intensity"}) x->fields.push_back({n, 'F', 4, 1});
  if (format == 1) {
    auto p = std::make_shared<capz::PLYExtra>();
    p->encoding = encoding[0] == 'a' ? "ascii" : "binary_little_endian";
    p->fields = x->fields;
    p->type_names = {"float", "float", "float32", "float"};
    p->comments = {"fuzz"};
    t.ply = p;
  } else if (format == 2) {
    t.bin = std::make_shared<capz::BinExtra>();
  }
  x->width = 5;
  for (size_t f = 0; f < frames; ++f) x->frame_names.push_back("f" + std::to_string(f) + ".pcd");
  t.pcd = x;
  capz::PointAttribute a;
  a.name = "intensity";
  a.type = 'F';
  a.size = 4;
  t.attributes.push_back(a);
  return t;
}

capz::FrameBlock make_block(size_t frames) {
  capz::FrameBlock b;
  b.reset(0, frames, 5, 0, false);
  for (size_t i = 0; i < frames * 5; ++i) {
    b.valid[i] = i != 1;
    for (int a = 0; a < 3; ++a) b.xyz[i * 3 + a] = 0.5 * static_cast<double>(i) - a;
  }
  b.attributes.assign(1, std::vector<uint8_t>(frames * 5 * 4));
  for (size_t i = 0; i < b.attributes[0].size(); ++i)
    b.attributes[0][i] = static_cast<uint8_t>(i * 7);
  return b;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const uint8_t mode = data[0];
  const size_t frames = 1 + ((mode >> 1) & 3);
  static const char* const kEnc[3] = {"ascii", "binary", "binary_compressed"};
  const capz::Take header = make_header(frames, kEnc[(mode >> 3) % 3], (mode >> 5) & 3);
  const capz::FrameBlock block = make_block(frames);
  ++data;
  --size;
  if (mode % 2 == 0) {
    capz::ByteReader in(data, size, "fuzz");
    try {
      const uint64_t n = in.varint();
      if (n > in.remaining()) return 0;
      const uint8_t* pcdr = in.bytes(static_cast<size_t>(n));
      capz::residue::PCDResidueDecoder dec(pcdr, static_cast<size_t>(n), header, "fuzz");
      std::vector<uint8_t> out;
      for (size_t k = 0; k < frames; ++k) dec.frame(block, k, in, header.pcd->frame_names[k], &out);
    } catch (const capz::Error&) {
    }
    return 0;
  }
  // Frame files: the writer's (each frame in an encoding picked by the input), then edited.
  capz::residue::PcdRegen regen(header);
  std::vector<std::vector<uint8_t>> files(frames);
  size_t at = 0;
  auto next = [&]() -> uint8_t { return at < size ? data[at++] : 0; };
  for (size_t k = 0; k < frames; ++k) {
    size_t he = 0;
    regen.frame(block, k, next() % regen.encodings(), &files[k], &he);
    const size_t edits = next() % 8;
    for (size_t e = 0; e < edits; ++e) {
      const uint8_t op = next(), v = next();
      const size_t pos =
          files[k].empty() ? 0 : (static_cast<size_t>(next()) * 257 + v) % files[k].size();
      if (op % 4 == 0 && !files[k].empty())
        files[k][pos] = v;
      else if (op % 4 == 1)
        files[k].insert(files[k].begin() + static_cast<long>(pos), v);
      else if (op % 4 == 2)
        files[k].push_back(v);
      else if (!files[k].empty())
        files[k].erase(files[k].begin() + static_cast<long>(pos));
    }
  }
  capz::residue::PCDResidueEncoder enc(header);
  const std::vector<uint8_t> pcdr = enc.file_part(files[0]);
  capz::ByteWriter w;
  for (size_t k = 0; k < frames; ++k)
    enc.frame(block, k, files[k], capz::hash128(files[k].data(), files[k].size()), w);
  capz::residue::PCDResidueDecoder dec(pcdr.data(), pcdr.size(), header, "fuzz");
  capz::ByteReader in(w.buffer().data(), w.size(), "fuzz PCDP");
  std::vector<uint8_t> out;
  for (size_t k = 0; k < frames; ++k) {
    dec.frame(block, k, in, header.pcd->frame_names[k], &out);
    CAPZ_FUZZ_CHECK(out == files[k]);
  }
  CAPZ_FUZZ_CHECK(in.at_end());
  return 0;
}
