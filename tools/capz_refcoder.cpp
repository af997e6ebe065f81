// The simple reference coder a user could write in an afternoon, to measure capz against:
// quantise every coordinate to the same grid capz uses (step = 2 x tolerance), predict each
// trajectory by linear extrapolation along time, store the integer residuals as int32, and let
// `xz -9e` (run by tools/bench) do the entropy coding.
//
//   capz_refcoder encode IN OUT.bin --tolerance T [--shape F N] [--mask M]
//   capz_refcoder decode IN.bin OUT.f32
//
// IN is any input capz reads (or a raw .f32 with --shape/--mask). Gaps are filled with the
// point's previous valid position before quantising (raw_io.h fill_gaps()), and the mask is
// stored so the decoder knows them.
//
// OUT.bin layout (little-endian): "CZRQ", u8 version = 1, u32 frames, u32 points, f64 step,
// the mask as frames*points bits (sample i = f * points + p at bit i % 8 of byte i / 8),
// then residuals as int32 in trajectory order (point, axis, frame).
// Quantiser: q = round(x / step) (half away from zero), reconstruction q * step, so |x - x'| <=
// step / 2 = T. Predictor: pred(0) = 0, pred(1) = q(0), pred(t) = 2 q(t-1) - q(t-2); residual q(t)
// - pred(t).
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "capz/error.h"
#include "coding/bytes.h"
#include "raw_io.h"

namespace {

const char kMagic[4] = {'C', 'Z', 'R', 'Q'};

int64_t predict(const int64_t* q, size_t t) {
  if (t == 0) return 0;
  if (t == 1) return q[0];
  return 2 * q[t - 1] - q[t - 2];
}

void encode(const std::string& in, const std::string& out, double tol, size_t frames, size_t points,
            const std::string& mask) {
  if (!(tol > 0)) capz::fail(capz::ErrorCode::kInvalidParameter, in, "tolerance must be > 0");
  capz::Take t = capz_tools::load_input(in, frames, points, mask);
  capz_tools::fill_gaps(&t);
  const double step = 2 * tol;
  capz::ByteWriter w;
  for (char c : kMagic) w.u8(static_cast<uint8_t>(c));
  w.u8(1);
  w.u32(static_cast<uint32_t>(t.frames));
  w.u32(static_cast<uint32_t>(t.points));
  w.f64(step);
  const size_t n = t.frames * t.points;
  for (size_t i = 0; i < n; i += 8) {
    uint8_t b = 0;
    for (size_t k = 0; k < 8 && i + k < n; ++k)
      b |= static_cast<uint8_t>((t.valid[i + k] ? 1 : 0) << k);
    w.u8(b);
  }
  std::vector<int64_t> q(t.frames);
  for (size_t p = 0; p < t.points; ++p)
    for (int axis = 0; axis < 3; ++axis) {
      for (size_t f = 0; f < t.frames; ++f) {
        double v = std::round(t.at(f, p)[axis] / step);  // half away from zero
        if (std::fabs(v) > 1e15)
          capz::fail(capz::ErrorCode::kInvalidParameter, in, "tolerance too small for the data");
        q[f] = static_cast<int64_t>(v);
      }
      for (size_t f = 0; f < t.frames; ++f) {
        int64_t r = q[f] - predict(q.data(), f);
        if (r < std::numeric_limits<int32_t>::min() || r > std::numeric_limits<int32_t>::max())
          capz::fail(capz::ErrorCode::kInvalidParameter, in,
                     "residual does not fit int32: tolerance too small for the data");
        w.i32(static_cast<int32_t>(r));
      }
    }
  capz_tools::write_bytes(out, w.buffer());
}

void decode(const std::string& in, const std::string& out) {
  std::vector<uint8_t> data = capz::read_file(in);
  capz::ByteReader r(data.data(), data.size(), in);
  for (char c : kMagic)
    if (r.u8() != static_cast<uint8_t>(c))
      capz::fail(capz::ErrorCode::kNotOurFormat, in, "not a reference-coder stream");
  if (r.u8() != 1) capz::fail(capz::ErrorCode::kUnsupportedVersion, in, "unknown version");
  size_t frames = r.u32(), points = r.u32();
  double step = r.f64();
  if (frames != 0 && points > data.size() / frames)
    capz::fail(capz::ErrorCode::kCorrupt, in, "stated shape larger than the file");
  size_t n = frames * points;
  if (r.remaining() != (n + 7) / 8 + n * 3 * 4)
    capz::fail(capz::ErrorCode::kCorrupt, in, "size does not match the stated shape");
  for (size_t i = 0; i < (n + 7) / 8; ++i) r.u8();  // the mask: metrics use the original's
  std::vector<double> xyz(n * 3);
  std::vector<int64_t> q(frames);
  for (size_t p = 0; p < points; ++p)
    for (int axis = 0; axis < 3; ++axis)
      for (size_t f = 0; f < frames; ++f) {
        q[f] = predict(q.data(), f) + static_cast<int32_t>(r.u32());
        xyz[(f * points + p) * 3 + axis] = static_cast<double>(q[f]) * step;
      }
  capz_tools::write_f32(out, xyz.data(), xyz.size());
}

int usage() {
  std::fprintf(stderr,
               "usage: capz_refcoder encode IN OUT.bin --tolerance T [--shape F N] [--mask M]\n"
               "       capz_refcoder decode IN.bin OUT.f32\n");
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) return usage();
  std::string mode = argv[1], in = argv[2], out = argv[3], mask;
  double tol = 0;
  size_t frames = 0, points = 0;
  for (int i = 4; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--tolerance" && i + 1 < argc) {
      tol = std::stod(argv[++i]);
    } else if (a == "--shape" && i + 2 < argc) {
      frames = std::stoul(argv[++i]);
      points = std::stoul(argv[++i]);
    } else if (a == "--mask" && i + 1 < argc) {
      mask = argv[++i];
    } else {
      return usage();
    }
  }
  try {
    if (mode == "encode") {
      encode(in, out, tol, frames, points, mask);
    } else if (mode == "decode") {
      decode(in, out);
    } else {
      return usage();
    }
  } catch (const capz::Error& e) {
    std::fprintf(stderr, "capz_refcoder: %s\n", e.what());
    return static_cast<int>(e.code());
  }
  return 0;
}
