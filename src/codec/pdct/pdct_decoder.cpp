// Decoder library (capz_decode): builds without PCL and without the transform encoders.
#include "codec/pdct/pdct_decoder.h"

#include <cmath>
#include <memory>
#include <string>

#include "capz/error.h"
#include "codec/pdct/pdct_shared.h"
#include "codec/pdct/predict.h"
#include "coding/bytes.h"
#include "coding/entropy.h"

namespace capz {
namespace pdct {
namespace {

// Closed-loop hooks (predict.h) of the DCT path: integers from the three streams.
class DecoderHooks : public LoopHooks {
 public:
  DecoderHooks(IntDecoder* seed, IntDecoder* first, IntDecoder* coef, size_t frame_points)
      : seed_(seed), first_(first), coef_(coef), sc_(frame_points) {}
  int64_t seed_residual(size_t, size_t k, int a, int64_t) override {
    int tok = 0;
    const int32_t r = seed_->get_signed(sc_.context(k, a), &tok);
    sc_.update(k, a, tok);
    return r;
  }
  int64_t first_residual(size_t, size_t, int a, const Lcf&, int64_t) override {
    return first_->get_signed(a);
  }
  void coefficients(size_t, size_t, const Lcf&, const double*, const BlockDct& dct,
                    int64_t* coefs) override {
    const size_t n = dct.size();
    for (int a = 0; a < 3; ++a)
      for (size_t b = 0; b < dct.blocks(); ++b) {
        const size_t o = dct.block_begin(b), len = dct.block_size(b);
        int prev = 0;
        for (size_t l = 0; l < len; ++l)
          coefs[a * n + o + l] = coef_->get_signed(coef_context(l, prev), &prev);
      }
  }

 private:
  IntDecoder *seed_, *first_, *coef_;
  SeedContexts sc_;
};

// Hooks of the grid path (predict.h): integers from the three streams.
class GridDecoderHooks : public GridHooks {
 public:
  GridDecoderHooks(IntDecoder* seed, IntDecoder* first, IntDecoder* resid, size_t points,
                   size_t frame_points)
      : seed_(seed), first_(first), resid_(resid), sc_(frame_points), last_(points * 3, 0) {}
  int64_t seed_residual(size_t, size_t k, int a, int64_t) override {
    int tok = 0;
    const int32_t r = seed_->get_signed(sc_.context(k, a), &tok);
    sc_.update(k, a, tok);
    return r;
  }
  int64_t point_residual(size_t f, uint32_t i, int a, int kind, int64_t) override {
    if (f == 0) return first_->get_signed(a);
    int tok = 0;
    uint8_t& last = last_[3 * static_cast<size_t>(i) + a];
    const int32_t r = resid_->get_signed(grid_context(kind, a, prev_tok_, last), &tok);
    prev_tok_ = tok;
    last = static_cast<uint8_t>(tok);
    return r;
  }

 private:
  IntDecoder *seed_, *first_, *resid_;
  SeedContexts sc_;
  int prev_tok_ = 0;
  std::vector<uint8_t> last_;
};

// Version, flags and steps (docs/CODEC-PDCT.md); *grid: the payload is in grid mode.
Steps read_header(ByteReader* r, bool* grid) {
  const uint8_t version = r->u8();
  if (version != kVersion)
    throw Error(ErrorCode::kUnsupportedVersion,
                std::string(kWhat) + ": version " + std::to_string(version) +
                    " (this build reads " + std::to_string(kVersion) + ")");
  const uint8_t flags = r->u8();
  if (flags & ~static_cast<unsigned>(kKnownFlags))
    throw Error(ErrorCode::kCorrupt, std::string(kWhat) + ": unknown flags");
  *grid = (flags & kFlagGrid) != 0;
  Steps S;
  S.seed_order = (flags & kFlagSeedOrder2) ? 2 : 1;
  S.local_order = (flags & kFlagLocalOrder2) ? 2 : 1;
  S.seed = r->f64();
  S.first = r->f64();
  S.coef = r->f64();
  for (double s : {S.seed, S.first, S.coef})
    if (!(s > 0) || !std::isfinite(s))
      throw Error(ErrorCode::kCorrupt, std::string(kWhat) + ": bad step");
  return S;
}

// Layout of a window of frames x points after the header; kinds: each point's predictor in grid
// mode (kLocal1 otherwise).
Layout read_layout(ByteReader* r, size_t frames, size_t points, bool grid,
                   std::vector<uint8_t>* kinds) {
  Layout L;
  L.frames = frames;
  L.points = points;
  L.dct_block = static_cast<size_t>(r->varint());
  if (L.dct_block < 1 || L.dct_block > kMaxDctBlock)
    throw Error(ErrorCode::kCorrupt,
                std::string(kWhat) + ": dct block " + std::to_string(L.dct_block));
  const uint64_t K = r->count(1, "frame point count");
  if (K > points)
    throw Error(ErrorCode::kCorrupt, std::string(kWhat) + ": more frame points than points");
  L.frame_points.resize(static_cast<size_t>(K));
  uint64_t at = 0;
  for (size_t k = 0; k < K; ++k) {
    const uint64_t g = r->varint();
    at = k == 0 ? g : at + 1 + g;
    if (g > points || at >= points)
      throw Error(ErrorCode::kCorrupt, std::string(kWhat) + ": frame point index out of range");
    L.frame_points[k] = static_cast<uint32_t>(at);
  }
  const uint64_t C = r->count(3, "cluster count");
  if (C == 0 || C > points + 1)
    throw Error(ErrorCode::kCorrupt, std::string(kWhat) + ": cluster count");
  L.triangles.resize(static_cast<size_t>(C));
  for (auto& t : L.triangles)
    for (auto& v : t) {
      const uint64_t x = r->varint();
      if (x > points)
        throw Error(ErrorCode::kCorrupt, std::string(kWhat) + ": triangle vertex out of range");
      v = static_cast<uint32_t>(x);
    }
  L.members.assign(static_cast<size_t>(C), {});
  std::vector<uint8_t> is_fp(points, 0);
  for (uint32_t p : L.frame_points) is_fp[p] = 1;
  const size_t rest = points - static_cast<size_t>(K);
  kinds->assign(points, kLocal1);
  {
    const size_t len = static_cast<size_t>(r->count(1, "cluster id block length"));
    const uint8_t* blk = r->bytes(len);
    const auto ids = decode_uints(blk, len, rest, std::string(kWhat) + " cluster ids");
    std::vector<uint32_t> ks;
    if (grid) {
      const size_t klen = static_cast<size_t>(r->count(1, "predictor block length"));
      const uint8_t* kblk = r->bytes(klen);
      ks = decode_uints(kblk, klen, rest, std::string(kWhat) + " predictors");
    }
    size_t j = 0;
    for (size_t i = 0; i < points; ++i) {
      if (is_fp[i]) continue;
      if (ids[j] >= C)
        throw Error(ErrorCode::kCorrupt, std::string(kWhat) + ": cluster id out of range");
      if (grid) {
        if (ks[j] >= static_cast<uint32_t>(kPointPredictors))
          throw Error(ErrorCode::kCorrupt, std::string(kWhat) + ": unknown predictor");
        (*kinds)[i] = static_cast<uint8_t>(ks[j]);
      }
      L.members[ids[j++]].push_back(static_cast<uint32_t>(i));
    }
  }
  return L;
}

}  // namespace
}  // namespace pdct

void PdctDecoder::decode(const uint8_t* data, size_t size, size_t frames, size_t points,
                         std::vector<double>* recon) const {
  using namespace pdct;
  ByteReader r(data, size, kWhat);
  bool grid = false;
  const Steps S = read_header(&r, &grid);
  std::vector<uint8_t> kinds;
  const Layout L = read_layout(&r, frames, points, grid, &kinds);
  check_layout(L, kWhat);
  auto block = [&](const char* name, int contexts) {
    const size_t len = static_cast<size_t>(r.count(1, name));
    const uint8_t* blk = r.bytes(len);
    return std::unique_ptr<IntDecoder>(
        new IntDecoder(blk, len, contexts, std::string(kWhat) + " " + name));
  };
  auto seed = block("frame-point block", kSeedContexts);
  auto first = block("frame-0 block", kFirstContexts);
  auto coef =
      grid ? block("residual block", kGridContexts) : block("coefficient block", kCoefContexts);
  if (!r.at_end()) throw Error(ErrorCode::kCorrupt, std::string(kWhat) + ": trailing bytes");
  if (grid) {
    GridDecoderHooks h(seed.get(), first.get(), coef.get(), points, L.frame_points.size());
    run_grid_loop(L, S.seed, S.seed_order, kinds, &h, recon);
  } else {
    DecoderHooks h(seed.get(), first.get(), coef.get(), L.frame_points.size());
    run_closed_loop(L, S, &h, recon);
  }
  if (!seed->at_end() || !first->at_end() || !coef->at_end())
    throw Error(ErrorCode::kCorrupt,
                std::string(kWhat) + ": an entropy-coded block has bytes left over");
}

}  // namespace capz
