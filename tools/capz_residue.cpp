// capz_residue FILE... [--via-capz DIR] [--block N]
// Measures the lossless residue (src/io/residue/) of C3D files and checks that it rebuilds each
// file byte for byte. Per file, one tab-separated line:
//   file  result  size  file_part  windows  residue  [capz  residue/capz]
// result: "exact" (rebuilt bytes hash to the original's XXH3-128), "DIFF", or "unreadable: why".
// --via-capz DIR: also compress the file --lossless into DIR and rebuild from the frames the
// .capz gives back (what decompress would see), and report the .capz size.
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/stream.h"
#include "core/hash.h"
#include "io/residue/c3d_residue.h"

using namespace capz;

namespace {

struct Row {
  uint64_t size = 0, file_part = 0, windows = 0, capz = 0;
  bool exact = false;
};

Row measure(const std::string& path, const std::string& via, size_t block) {
  Row r;
  auto src = open_c3d_frames(path);
  residue::C3DResidueEncoder enc(path);
  const size_t F = src->header().frames;
  std::vector<std::vector<uint8_t>> wins;
  FrameBlock b;
  for (size_t f = 0; f < F; f += block) {
    src->read(f, std::min(block, F - f), &b);
    wins.push_back(enc.window(b));
    r.windows += wins.back().size();
  }
  const std::vector<C3DGroup>& groups = src->header().c3d->groups;
  const std::vector<uint8_t> part = enc.file_part(groups);
  r.file_part = part.size();
  r.size = enc.layout().file_size();

  std::unique_ptr<FrameSource> back = std::move(src);
  if (!via.empty()) {
    const std::string out = via + "/residue_probe.capz";
    CompressOptions opts;
    opts.lossless = true;
    CompressStats stats;
    auto again = open_c3d_frames(path);
    compress_stream(*again, opts, out, true, &stats);
    back = open_capz_frames(out);
    InputFile capz(out);
    r.capz = capz.size();
  }
  residue::C3DResidueDecoder dec(part.data(), part.size(), back->header().c3d->groups, path);
  Hasher h;
  h.update(dec.head().data(), dec.head().size());
  std::vector<uint8_t> bytes;
  for (size_t f = 0, w = 0; f < F; f += block, ++w) {
    back->read(f, std::min(block, F - f), &b);
    bytes.clear();
    dec.window(b, wins[w].data(), wins[w].size(), &bytes);
    h.update(bytes.data(), bytes.size());
  }
  h.update(dec.tail().data(), dec.tail().size());
  r.exact = h.digest() == hash128_file(path);
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  std::string via;
  size_t block = 1024;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--via-capz" && i + 1 < argc)
      via = argv[++i];
    else if (a == "--block" && i + 1 < argc)
      block = std::strtoul(argv[++i], nullptr, 10);
    else
      files.push_back(a);
  }
  if (files.empty() || block == 0) {
    std::fprintf(stderr, "usage: capz_residue FILE... [--via-capz DIR] [--block N]\n");
    return 2;
  }
  int bad = 0;
  std::printf("file\tresult\tsize\tfile_part\twindows\tresidue\tcapz\tresidue/capz\n");
  for (const auto& f : files) {
    try {
      Row r = measure(f, via, block);
      const uint64_t res = r.file_part + r.windows;
      std::printf("%s\t%s\t%llu\t%llu\t%llu\t%llu\t%llu\t%.4f\n", f.c_str(),
                  r.exact ? "exact" : "DIFF", (unsigned long long)r.size,
                  (unsigned long long)r.file_part, (unsigned long long)r.windows,
                  (unsigned long long)res, (unsigned long long)r.capz,
                  r.capz ? double(res) / double(r.capz) : 0.0);
      bad += !r.exact;
    } catch (const Error& e) {
      std::printf("%s\tunreadable: %s\n", f.c_str(), e.what());
    }
  }
  return bad ? 1 : 0;
}
