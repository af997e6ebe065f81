// capz_residue FILE... [--via-capz DIR] [--block N]
// Measures the lossless residue (src/io/residue/) of C3D and TRC files and checks that it rebuilds
// each file byte for byte. Per file, one tab-separated line:
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
#include "capz/io.h"
#include "capz/stream.h"
#include "core/hash.h"
#include "io/residue/c3d_residue.h"
#include "io/residue/trc_residue.h"

using namespace capz;

namespace {

struct Row {
  uint64_t size = 0, file_part = 0, windows = 0, capz = 0;
  bool exact = false;
};

Row measure(const std::string& path, const std::string& via, size_t block) {
  Row r;
  const bool trc = detect_format(path) == Format::kTRC;
  auto src = trc ? open_trc_frames(path) : open_c3d_frames(path);
  const residue::FileResidue res = trc ? residue::encode_trc_residue(path, *src, block)
                                       : residue::encode_c3d_residue(path, *src, block);
  r.file_part = res.file_part.size();
  r.windows = res.bytes() - r.file_part;
  std::unique_ptr<FrameSource> back = std::move(src);
  if (!via.empty()) {
    const std::string out = via + "/residue_probe.capz";
    CompressOptions opts;
    opts.lossless = true;
    auto again = trc ? open_trc_frames(path) : open_c3d_frames(path);
    compress_stream(*again, opts, out, true);
    back = open_capz_frames(out);
    r.capz = InputFile(out).size();
  }
  Hasher h;
  auto write = [&](const uint8_t* p, size_t n) {
    h.update(p, n);
    r.size += n;
  };
  if (trc)
    residue::rebuild_trc(res, *back, block, write, path);
  else
    residue::rebuild_c3d(res, *back, block, write, path);
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
