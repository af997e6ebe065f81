// The analog window's decoder (docs/FORMAT.md 11): the channel headers, then each channel's
// samples from the entropy-coded block; the encoder is analog_codec_encode.cpp.
#include "coding/analog/analog_codec.h"

#include "capz/error.h"
#include "coding/analog/analog_cascade.h"
#include "coding/analog/analog_cross.h"
#include "coding/analog/analog_entropy.h"
#include "coding/analog/analog_float.h"
#include "coding/analog/analog_interp.h"
#include "coding/analog/analog_layout.h"
#include "coding/analog/analog_lpc.h"
#include "coding/analog/analog_repeat.h"
#include "coding/analog/analog_scratch.h"
#include "coding/analog/analog_window.h"
#include "coding/bytes.h"

namespace capz {
namespace {

using analog::ChannelRepr;
using analog::Kind;
using namespace analog::window;

// Side information of one LPC block (9.1), as put_lpc (analog_codec_encode.cpp) writes it.
analog::LpcParams get_lpc(IntDecoder::Cursor* dec) {
  analog::LpcParams p;
  int tok;
  p.order = static_cast<int>(dec->get(analog::kParamContext, &tok));
  if (p.order == analog::kLpcConstantOrder) {
    p.order = 0;
    p.constant = dec->get_signed(analog::kCoefContext, &tok);
    if (p.constant > analog::kMaxSample || p.constant < -analog::kMaxSample)
      dec->corrupt("analog constant prediction out of range");
    return p;
  }
  if (p.order > analog::kMaxLpcOrder) dec->corrupt("analog LPC order above 32");
  if (p.order == 0) return p;
  p.shift = static_cast<int>(dec->get(analog::kParamContext, &tok));
  if (p.shift > analog::kMaxLpcShift) dec->corrupt("analog LPC shift above 20");
  for (int j = 0; j < p.order; ++j) {
    const int32_t q = dec->get_signed(analog::kCoefContext, &tok);
    if (q >= (1 << analog::kLpcPrecision) || q <= -(1 << analog::kLpcPrecision))
      dec->corrupt("analog LPC coefficient out of range");
    p.q.push_back(q);
  }
  return p;
}

// Samples [b0, b1) of an integer channel, the stage flags fixed at compile time (FORMAT.md
// 4.2.5, 9.5, 9.7).
template <bool kCascade, bool kRef>
void decode_int_block(size_t b0, size_t b1, const analog::LpcParams& p, const int32_t* ref,
                      int32_t beta, IntDecoder::Cursor* dec, analog::Magnitude* mag,
                      analog::SignLms* lms, int32_t* xs, double* xd, int32_t* r1) {
  const analog::LpcKernel lpc(p);
  const size_t order = static_cast<size_t>(p.order);
  for (size_t i = b0; i < b1; ++i) {
    int64_t e = analog::get_residual_v2(dec, mag);
    if (kCascade) {
      const int64_t out = e;
      e += lms->predict();
      lms->update(e, out);
    }
    if (kRef) e += analog::cross_predict(beta, ref[i]);
    const int64_t v = e + (i >= order ? lpc.predict(xd + i) : i ? xs[i - 1] : 0);
    if (v > analog::kMaxSample || v < -analog::kMaxSample)
      dec->corrupt("analog sample out of range");
    xs[i] = static_cast<int32_t>(v);
    xd[i] = static_cast<double>(v);
    r1[i] = static_cast<int32_t>(e);
  }
}

void decode_int_blocks(size_t b0, size_t b1, bool cascade, const analog::LpcParams& p,
                       const int32_t* ref, int32_t beta, IntDecoder::Cursor* dec,
                       analog::Magnitude* mag, analog::SignLms* lms, int32_t* xs, double* xd,
                       int32_t* r1) {
  if (cascade && ref)
    decode_int_block<true, true>(b0, b1, p, ref, beta, dec, mag, lms, xs, xd, r1);
  else if (cascade)
    decode_int_block<true, false>(b0, b1, p, ref, beta, dec, mag, lms, xs, xd, r1);
  else if (ref)
    decode_int_block<false, true>(b0, b1, p, ref, beta, dec, mag, lms, xs, xd, r1);
  else
    decode_int_block<false, false>(b0, b1, p, ref, beta, dec, mag, lms, xs, xd, r1);
}

void decode_int_channel(size_t n, const std::vector<const std::vector<int32_t>*>& refs,
                        IntDecoder::Cursor* dec, std::vector<int32_t>* x,
                        std::vector<int32_t>* r1) {
  x->resize(n);
  r1->resize(n);
  int tok;
  const uint32_t cascade = dec->get(analog::kParamContext, &tok);
  if (cascade > 1) dec->corrupt("bad analog cascade flag");
  analog::CrossParams cross;
  cross.distance = static_cast<int>(dec->get(analog::kParamContext, &tok));
  if (cross.distance > static_cast<int>(refs.size()) ||
      (cross.distance && !refs[cross.distance - 1]))
    dec->corrupt(
        "analog inter-channel reference is not an integer channel with the same repeated "
        "frames");
  if (cross.distance) {
    cross.beta = dec->get_signed(analog::kCoefContext, &tok);
    if (cross.beta >= analog::kMaxBeta || cross.beta <= -analog::kMaxBeta)
      dec->corrupt("analog inter-channel weight out of range");
  }
  const int32_t* ref = cross.distance ? refs[cross.distance - 1]->data() : nullptr;
  analog::Magnitude mag;
  analog::SignLms lms;
  std::vector<double> xd(n + analog::kMaxLpcOrder, 0.0);
  double* xs_d = xd.data() + analog::kMaxLpcOrder;
  for (size_t b0 = 0; b0 < n; b0 += kBlockRows) {
    const size_t b1 = std::min(n, b0 + kBlockRows);
    const analog::LpcParams p = get_lpc(dec);
    decode_int_blocks(b0, b1, cascade, p, ref, cross.beta, dec, &mag, &lms, x->data(), xs_d,
                      r1->data());
  }
}

}  // namespace

void decode_analog_window(const uint8_t* data, size_t size, size_t nrows, int channels,
                          double* rows, const std::string& what, size_t repeat_S) {
  const analog::HeaderRules rules = header_rules(repeat_S);
  ByteReader in(data, size, what);
  const int version = in.u8();
  if (version != kWindowVersion)
    throw Error(ErrorCode::kCorrupt, what + ": unknown analog window version " +
                                         std::to_string(version) + " (format 1.0 has 2)");
  const uint64_t head_size = in.count(1, "analog header size");
  ByteReader head(in.bytes(static_cast<size_t>(head_size)), static_cast<size_t>(head_size), what);
  const size_t nch = static_cast<size_t>(std::max(channels, 0));
  std::vector<ChannelRepr> reprs;
  std::vector<analog::KeptRows> layouts(nch);  // FORMAT.md 11.3, 11.4, 11.5
  std::vector<size_t> kept(nch, nrows);        // each channel's coded samples
  analog::HeaderState state;
  bool any_coded = false;
  for (size_t c = 0; c < nch; ++c) {
    reprs.push_back(analog::read_repr_header(&head, nrows, rules, &state, &layouts[c]));
    kept[c] = layouts[c].count(nrows, repeat_S);
    any_coded |= coded(reprs.back().kind);
  }
  if (!head.at_end())
    throw Error(ErrorCode::kCorrupt, what + ": analog header has bytes left over");
  // The channel's samples into its column of rows: directly, or through its kept samples.
  std::vector<double> tmp;
  auto put = [&](size_t c) {
    double* column = nrows > 0 ? rows + c : rows;  // no rows: rows may be null (no offset)
    if (layouts[c].all()) {
      analog::reconstruct(reprs[c], nrows, column, nch, what);
      return;
    }
    tmp.resize(kept[c]);
    analog::reconstruct(reprs[c], kept[c], tmp.data(), 1, what);
    layouts[c].expand(tmp.data(), nrows, repeat_S, column, nch, what);
  };
  if (!any_coded) {
    if (!in.at_end())
      throw Error(ErrorCode::kCorrupt, what + ": analog window has bytes left over");
    for (size_t c = 0; c < nch; ++c) put(c);
    return;
  }
  IntDecoder ent(data + in.offset(), in.remaining(), analog::kAnalogContexts, what);
  analog::start_low_bit_models(&ent);
  IntDecoder::Cursor cur = ent.cursor();
  std::vector<std::vector<int32_t>> r1s(nch);
  std::vector<bool> has_r1(nch, false);
  for (size_t c = 0; c < nch; ++c) {
    ChannelRepr& r = reprs[c];
    if (analog::is_integer_kind(r.kind)) {
      std::vector<bool> use(nch, false);  // the same kept rows (FORMAT.md 11.3, 11.4, 11.5)
      for (size_t j = 0; j < c; ++j) use[j] = has_r1[j] && layouts[j] == layouts[c];
      decode_int_channel(kept[c], cross_refs(r1s, use, static_cast<int>(c)), &cur, &r.ints,
                         &r1s[c]);
      has_r1[c] = true;
    } else if (r.kind == Kind::kFloat32 || r.kind == Kind::kFloat64)
      analog::decode_float_channel(kept[c], r.kind == Kind::kFloat32, &cur, &r.filled);
    put(c);
    std::vector<int32_t>().swap(r.ints);
    std::vector<double>().swap(r.filled);
  }
  ent.commit(cur);
  if (!ent.at_end())
    throw Error(ErrorCode::kCorrupt, what + ": analog samples have bytes left over");
}

}  // namespace capz
