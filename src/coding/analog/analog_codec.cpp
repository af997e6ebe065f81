#include "coding/analog/analog_codec.h"

#include "capz/error.h"
#include "coding/analog/analog_cascade.h"
#include "coding/analog/analog_cross.h"
#include "coding/analog/analog_entropy.h"
#include "coding/analog/analog_float.h"
#include "coding/analog/analog_interp.h"
#include "coding/analog/analog_layout.h"
#include "coding/analog/analog_lpc.h"
#include "coding/analog/analog_pick.h"
#include "coding/analog/analog_repeat.h"
#include "coding/analog/analog_scratch.h"
#include "coding/bytes.h"
namespace capz {
namespace {

using analog::ChannelRepr;
using analog::Kind;

constexpr size_t kBlockRows = 4096;  // LPC block length (A.3)
// Candidates whose estimated size is above this times the smallest estimate are not
// trial-coded (analog::pick_smallest). On the 98 C3D takes of capz_analog_bench, 1.2 codes
// 5,273,482 bytes for the 5,273,240 of trying every candidate (5,219,447 for 5,219,153 with
// --repeats), and trial-codes about a fifth of the samples that trying all would.
constexpr double kTrialMargin = 1.2;
// What a coded sample costs beyond its residual's bit length, in the candidates' estimates (9.2
// streams on): a zero residual has no bits of length, yet a candidate that leaves out held or
// repeated samples saves their tokens (FORMAT.md 11.5). 1 bit: 124 bytes less on the 98 shared
// takes than 0, the same as 2, at the same speed.
constexpr uint64_t kEstimateBitsPerSample = 1;
// The window's version byte (FORMAT.md 11.1): 0; from 9.2 on 1, whose integer residuals code
// the two bits below their token through a model (11.10); from 9.3 on 2, which codes their tokens
// relative to the magnitude context as well (11.10). It says how integer residuals are coded.
constexpr int kWindowVersion = 0, kWindowVersionLowBits = 1, kWindowVersionRelative = 2;
// The version of the windows capz writes into a stream of this version.
int window_version(FormatVersion format) {
  return format >= kAnalogRelativeSince  ? kWindowVersionRelative
         : format >= kAnalogLowBitsSince ? kWindowVersionLowBits
                                         : kWindowVersion;
}
// Whether a window of this version starts the low-bit models on their symbols (FORMAT.md 11.10).
template <typename Coder>
void start_models(int version, Coder* coder) {
  if (version >= kWindowVersionLowBits) analog::start_low_bit_models(coder);
}

// Whether a channel of this kind has numbers in the entropy-coded block (a window whose
// channels have none omits the block).
bool coded(Kind k) {
  return k != Kind::kConst;
}

// Side information of one LPC block: order, then shift and coefficients; or the constant
// predictor's order code and its constant (9.1).
void put_lpc(const analog::LpcParams& p, IntEncoder::Cursor* enc) {
  if (p.order == 0 && p.constant != 0) {
    enc->put(static_cast<uint32_t>(analog::kLpcConstantOrder), analog::kParamContext);
    enc->put_signed(p.constant, analog::kCoefContext);
    return;
  }
  enc->put(static_cast<uint32_t>(p.order), analog::kParamContext);
  if (p.order == 0) return;
  enc->put(static_cast<uint32_t>(p.shift), analog::kParamContext);
  for (int32_t q : p.q) enc->put_signed(q, analog::kCoefContext);
}
// constant: a 9.1 or later stream, where the constant predictor's order code is valid.
analog::LpcParams get_lpc(IntDecoder::Cursor* dec, bool constant) {
  analog::LpcParams p;
  int tok;
  p.order = static_cast<int>(dec->get(analog::kParamContext, &tok));
  if (p.order == analog::kLpcConstantOrder && constant) {
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

// The LPC stage of a whole channel: per-block parameters and the residuals x - p, where the
// first min(order, ...) samples of the window are predicted by the previous sample (0 for the
// first) and the others by the block's LPC. *tally: the residuals' tokens (token_cost_bits).
void lpc_stage(const std::vector<int32_t>& x, std::vector<analog::LpcParams>* params,
               std::vector<int32_t>* r, bool constant, analog::TokenTally* tally) {
  r->resize(x.size());
  // The samples as doubles after kMaxLpcOrder zeros (analog::LpcKernel reads before the first).
  double* xd =
      analog::scratch<double, analog::Scratch::kLpcSamples>(x.size() + analog::kMaxLpcOrder);
  std::fill(xd, xd + analog::kMaxLpcOrder, 0.0);
  double* xs = xd + analog::kMaxLpcOrder;
  for (size_t i = 0; i < x.size(); ++i) xs[i] = x[i];
  for (size_t b0 = 0; b0 < x.size(); b0 += kBlockRows) {
    const size_t b1 = std::min(x.size(), b0 + kBlockRows);
    // The block's residuals by its predictor, then the head's by the previous sample.
    params->push_back(analog::choose_block_predictor(x.data() + b0, xs + b0, b1 - b0,
                                                     r->data() + b0, constant, tally));
    const size_t head = std::min(b1, std::max(b0, static_cast<size_t>(params->back().order)));
    for (size_t i = b0; i < head; ++i) {
      tally->remove((*r)[i]);
      (*r)[i] = static_cast<int32_t>(x[i] - (i ? x[i - 1] : 0));
      tally->add((*r)[i]);
    }
  }
}

// The LPC residuals of the channels before c that can serve as references (A.3.2).
std::vector<const std::vector<int32_t>*> cross_refs(const std::vector<std::vector<int32_t>>& r1s,
                                                    const std::vector<bool>& has, int c) {
  std::vector<const std::vector<int32_t>*> refs;
  for (int d = 1; d <= analog::kMaxCrossDistance && c - d >= 0; ++d)
    refs.push_back(has[c - d] ? &r1s[c - d] : nullptr);
  return refs;
}

// Their energies (analog::reference_energy), 0 where there is no reference.
std::vector<double> cross_energies(const std::vector<double>& energy, const std::vector<bool>& has,
                                   int c) {
  std::vector<double> e;
  for (int d = 1; d <= analog::kMaxCrossDistance && c - d >= 0; ++d)
    e.push_back(has[c - d] ? energy[c - d] : 0.0);
  return e;
}

// What the encoder decided for an integer channel: computed once, then coded into trial
// encoders and the window's encoder alike.
struct IntPlan {
  std::vector<analog::LpcParams> params;
  bool cascade = false;
  analog::CrossParams cross;
  std::vector<int32_t> r1;  // LPC residuals (a later channel's reference)
  std::vector<int32_t> r;   // the residuals coded
  uint64_t bits = 0;        // their summed bit lengths (a guess of the coded size)
};

// Four pipelines (reference or not, cascade or not); the one kept has the smallest order-0
// entropy of its tokens (token_cost_bits). The summed bit lengths, a cruder guess that often
// picked the cascade where it turned exact zeros into +-1, stay the plan's estimate.
void plan_int_channel(const std::vector<int32_t>& x,
                      const std::vector<const std::vector<int32_t>*>& refs,
                      const std::vector<double>& ref_energy, bool constant, IntPlan* plan) {
  analog::TokenTally r1_tokens;
  lpc_stage(x, &plan->params, &plan->r1, constant, &r1_tokens);
  const std::vector<int32_t>& r1 = plan->r1;
  const size_t n = r1.size();
  analog::CrossParams cross = analog::choose_cross(r1, refs, ref_energy);
  // The other three pipelines' residuals in per-thread buffers; the one kept is copied out.
  int32_t* with_ref = analog::scratch<int32_t, analog::Scratch::kWithReference>(n);
  int32_t* plain_lms = analog::scratch<int32_t, analog::Scratch::kPlainCascade>(n);
  int32_t* ref_lms = analog::scratch<int32_t, analog::Scratch::kRefCascade>(n);
  if (cross.distance) {
    const std::vector<int32_t>& ref = *refs[cross.distance - 1];
    for (size_t i = 0; i < n; ++i)
      with_ref[i] = static_cast<int32_t>(r1[i] - analog::cross_predict(cross.beta, ref[i]));
  }
  const auto plain_cost = analog::sign_lms_run(r1.data(), n, plain_lms);
  const auto ref_cost = cross.distance ? analog::sign_lms_run(with_ref, n, ref_lms) : plain_cost;
  const uint64_t costs[4] = {plain_cost.first, plain_cost.second, ref_cost.first, ref_cost.second};
  const int32_t* res[4] = {r1.data(), plain_lms, with_ref, ref_lms};
  int best = 0;
  double best_tok = 0;
  for (int k = 0; k < (cross.distance ? 4 : 2); ++k) {
    // The LPC residuals' histogram came with the predictors' choice (the same double).
    const double tok = k == 0 ? r1_tokens.bits(n) : analog::token_cost_bits(res[k], n);
    if (k == 0 || tok < best_tok) {
      best = k;
      best_tok = tok;
    }
  }
  plan->bits = costs[best];
  plan->cascade = best & 1;
  if (best < 2) cross = analog::CrossParams();
  plan->cross = cross;
  plan->r.assign(res[best], res[best] + n);
}

// Integer channel: the cascade flag, the reference distance (and beta), then per block the LPC
// parameters and residuals (as a window of `version` codes them: FORMAT.md 11.10).
// Stops, returning false, once enc->bytes_out() reaches `limit` (checked every kTrialCheck
// samples). Everything it calls is inlined (flatten) and it codes through a local copy of the
// cursor, which then stays in registers (entropy.h's Cursor).
__attribute__((flatten)) bool emit_int_channel(const IntPlan& plan, int version,
                                               IntEncoder::Cursor* out, size_t limit = SIZE_MAX) {
  IntEncoder::Cursor c = *out;
  IntEncoder::Cursor* enc = &c;
  enc->put(plan.cascade ? 1 : 0, analog::kParamContext);
  enc->put(static_cast<uint32_t>(plan.cross.distance), analog::kParamContext);
  if (plan.cross.distance) enc->put_signed(plan.cross.beta, analog::kCoefContext);
  analog::Magnitude mag;
  const size_t n = plan.r.size();
  for (size_t b0 = 0, b = 0; b0 < n; b0 += kBlockRows, ++b) {
    const size_t b1 = std::min(n, b0 + kBlockRows);
    put_lpc(plan.params[b], enc);
    for (size_t i0 = b0; i0 < b1; i0 += analog::kTrialCheck) {
      if (enc->bytes_out() >= limit) return false;  // a stopped trial: its cursor is dropped
      const size_t i1 = std::min(b1, i0 + analog::kTrialCheck);
      if (version == kWindowVersionRelative)
        for (size_t i = i0; i < i1; ++i) analog::put_residual_v2(enc, &mag, plan.r[i]);
      else if (version == kWindowVersionLowBits)
        for (size_t i = i0; i < i1; ++i) analog::put_residual_v1(enc, &mag, plan.r[i]);
      else
        for (size_t i = i0; i < i1; ++i) analog::put_residual(enc, &mag, plan.r[i]);
    }
  }
  *out = c;
  return true;
}

// Samples [b0, b1) of an integer channel, the stage flags and the window version (FORMAT.md
// 4.2.5, 9.5, 9.7) fixed at compile time.
template <bool kCascade, bool kRef, int kVersion>
void decode_int_block(size_t b0, size_t b1, const analog::LpcParams& p, const int32_t* ref,
                      int32_t beta, IntDecoder::Cursor* dec, analog::Magnitude* mag,
                      analog::SignLms* lms, int32_t* xs, double* xd, int32_t* r1) {
  const analog::LpcKernel lpc(p);
  const size_t order = static_cast<size_t>(p.order);
  for (size_t i = b0; i < b1; ++i) {
    int64_t e = kVersion == kWindowVersionRelative  ? analog::get_residual_v2(dec, mag)
                : kVersion == kWindowVersionLowBits ? analog::get_residual_v1(dec, mag)
                                                    : analog::get_residual(dec, mag);
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

template <int kVersion>
void decode_int_blocks(size_t b0, size_t b1, bool cascade, const analog::LpcParams& p,
                       const int32_t* ref, int32_t beta, IntDecoder::Cursor* dec,
                       analog::Magnitude* mag, analog::SignLms* lms, int32_t* xs, double* xd,
                       int32_t* r1) {
  if (cascade && ref)
    decode_int_block<true, true, kVersion>(b0, b1, p, ref, beta, dec, mag, lms, xs, xd, r1);
  else if (cascade)
    decode_int_block<true, false, kVersion>(b0, b1, p, ref, beta, dec, mag, lms, xs, xd, r1);
  else if (ref)
    decode_int_block<false, true, kVersion>(b0, b1, p, ref, beta, dec, mag, lms, xs, xd, r1);
  else
    decode_int_block<false, false, kVersion>(b0, b1, p, ref, beta, dec, mag, lms, xs, xd, r1);
}

void decode_int_channel(size_t n, const std::vector<const std::vector<int32_t>*>& refs,
                        bool constant, int version, IntDecoder::Cursor* dec,
                        std::vector<int32_t>* x, std::vector<int32_t>* r1) {
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
    const analog::LpcParams p = get_lpc(dec, constant);
    int32_t* xs = x->data();
    int32_t* rs = r1->data();
    if (version == kWindowVersionRelative)
      decode_int_blocks<kWindowVersionRelative>(b0, b1, cascade, p, ref, cross.beta, dec, &mag,
                                                &lms, xs, xs_d, rs);
    else if (version == kWindowVersionLowBits)
      decode_int_blocks<kWindowVersionLowBits>(b0, b1, cascade, p, ref, cross.beta, dec, &mag, &lms,
                                               xs, xs_d, rs);
    else
      decode_int_blocks<kWindowVersion>(b0, b1, cascade, p, ref, cross.beta, dec, &mag, &lms, xs,
                                        xs_d, rs);
  }
}

// What the window's channel headers may carry in a stream of this version.
analog::HeaderRules header_rules(FormatVersion format, size_t repeat_S) {
  analog::HeaderRules rules;
  rules.S = repeat_S;
  rules.lattice = format >= kAnalogLatticeSince;
  rules.interp = format >= kAnalogFloat9Since;
  rules.hold = format >= kAnalogHoldSince;
  rules.share = format >= kAnalogShareSince;
  return rules;
}

// One channel's candidates: representations of all its rows, then, when it is not constant
// and a layout keeps fewer rows (its repeated frames, FORMAT.md 11.3; else its interpolation, 11.4,
// or its hold, 11.5), representations of the kept samples.
struct ChannelCandidates {
  std::vector<ChannelRepr> reprs;
  std::vector<analog::KeptRows> layouts;  // [0]: every row
  std::vector<size_t> layout_at;          // reprs[k] keeps the rows of layouts[layout_at[k]]
  const analog::KeptRows& layout(size_t k) const { return layouts[layout_at[k]]; }
};

ChannelCandidates channel_candidates(const double* col, size_t nrows, size_t repeat_S,
                                     const analog::ChannelHint& hint, FormatVersion format) {
  ChannelCandidates cc;
  cc.reprs = analog::candidate_representations(col, 1, nrows, hint);
  cc.layouts.resize(1);
  cc.layout_at.assign(cc.reprs.size(), 0);
  if (cc.reprs[0].kind == Kind::kConst) return cc;
  const size_t frames = repeat_S > 0 && nrows % repeat_S == 0 ? nrows / repeat_S : 0;
  analog::KeptRows more;
  if (frames) more.repeats = analog::repeated_frames(col, 1, frames, repeat_S);
  if (more.repeats.empty() && format >= kAnalogFloat9Since)
    analog::find_interpolation(col, 1, nrows, &more.interp);
  // A channel held for P > 2 rows also interpolates at period 2 with exceptions around its
  // changes: the layout with fewer kept samples is offered.
  analog::Hold hold;
  if (more.repeats.empty() && format >= kAnalogHoldSince &&
      analog::find_hold(col, 1, nrows, &hold) &&
      (more.interp.period == 0 ||
       analog::hold_kept_count(nrows, hold) < analog::interp_kept_count(nrows, more.interp))) {
    more.interp = analog::Interp();
    more.hold = std::move(hold);
  }
  if (more.all()) return cc;
  const std::vector<double> kept = more.samples(col, 1, nrows, repeat_S);
  for (ChannelRepr& m : analog::candidate_representations(kept.data(), 1, kept.size(), hint))
    if (m.kind != Kind::kConst || (more.interp.period == 0 && more.hold.period == 0)) {
      // 9.2, 9.4: kind 0 is corrupt with an interpolation or hold field
      cc.reprs.push_back(std::move(m));
      cc.layout_at.push_back(1);
    }
  cc.layouts.push_back(std::move(more));
  return cc;
}

// What a channel takes from the window's earlier channels: each integer channel's LPC residuals
// with their energy (references, A.3.2), and the rows each channel kept.
struct EarlierChannels {
  std::vector<std::vector<int32_t>> r1s;
  std::vector<double> energy;
  std::vector<bool> has_r1;
  std::vector<analog::KeptRows> layouts;
  explicit EarlierChannels(size_t channels)
      : r1s(channels), energy(channels, 0.0), has_r1(channels, false), layouts(channels) {}
};

// Each candidate's coding, decided once and then coded into trial encoders and the window's
// encoder alike: integer kinds the pipeline, float kinds the predictor.
struct CandidatePlans {
  std::vector<IntPlan> ints;
  std::vector<analog::FloatPlan> floats;
  std::vector<uint64_t> bits;  // summed bit lengths of what each codes
};

bool is_float_kind(Kind k) {
  return k == Kind::kFloat32 || k == Kind::kFloat64;
}

// A candidate's references are the earlier integer channels that keep the same rows.
CandidatePlans plan_candidates(const ChannelCandidates& cc, const EarlierChannels& earlier, int c,
                               FormatVersion format) {
  const size_t C = earlier.has_r1.size();
  std::vector<std::vector<bool>> use(cc.layouts.size(), std::vector<bool>(C));
  for (size_t l = 0; l < cc.layouts.size(); ++l)
    for (size_t j = 0; j < C; ++j)
      use[l][j] = earlier.has_r1[j] && earlier.layouts[j] == cc.layouts[l];
  const size_t K = cc.reprs.size();
  CandidatePlans p;
  p.ints.resize(K);
  p.floats.resize(K);
  p.bits.assign(K, 0);
  for (size_t k = 0; k < K; ++k) {
    const ChannelRepr& r = cc.reprs[k];
    if (analog::is_integer_kind(r.kind)) {
      const std::vector<bool>& u = use[cc.layout_at[k]];
      plan_int_channel(r.ints, cross_refs(earlier.r1s, u, c), cross_energies(earlier.energy, u, c),
                       format >= kAnalogConstantSince, &p.ints[k]);
      p.bits[k] = p.ints[k].bits;
    } else if (is_float_kind(r.kind)) {
      const bool f32 = r.kind == Kind::kFloat32;
      if (format >= kAnalogFloat9Since)
        p.floats[k] = analog::choose_float_plan9(r.filled, f32, &p.bits[k]);
      else
        p.floats[k].predictor = analog::choose_float_predictor(r.filled, f32, &p.bits[k]);
    }
  }
  return p;
}

// Codes candidate k's samples; false when the coding stopped at `limit` bytes out (a trial that
// cannot win).
bool emit_candidate(const ChannelCandidates& cc, const CandidatePlans& p, size_t k, int version,
                    IntEncoder::Cursor* enc, size_t limit) {
  const ChannelRepr& r = cc.reprs[k];
  if (analog::is_integer_kind(r.kind)) return emit_int_channel(p.ints[k], version, enc, limit);
  if (is_float_kind(r.kind))
    return analog::encode_float_channel(r.filled, r.kind == Kind::kFloat32, p.floats[k], enc,
                                        limit);
  return true;
}

// The candidate a channel keeps, measured: each candidate coded alone (fresh models), the
// smallest kept (the first of equals), tried in the order of their header bytes plus residual
// bit lengths; those estimated above kTrialMargin times the smallest estimate are not tried. A
// candidate's size is at least its header, one byte of block length and the bytes its coder has
// output so far: its trial stops once that reaches the bound. heads and states get each
// candidate's header, written from `state`, and the state after it.
size_t pick_candidate(const ChannelCandidates& cc, const CandidatePlans& p,
                      const analog::HeaderRules& rules, const analog::HeaderState& state,
                      size_t nrows, FormatVersion format, std::vector<std::vector<uint8_t>>* heads,
                      std::vector<analog::HeaderState>* states) {
  const size_t K = cc.reprs.size();
  const int version = window_version(format);
  std::vector<double> estimate(K);
  heads->resize(K);
  states->assign(K, state);
  for (size_t k = 0; k < K; ++k) {
    ByteWriter th;
    analog::write_repr_header(cc.reprs[k], cc.layout(k), rules, &(*states)[k], &th);
    (*heads)[k] = std::move(th.buffer());
    // From 9.2 on the estimates count kEstimateBitsPerSample a coded sample (earlier versions
    // code as they did).
    const uint64_t samples = format >= kAnalogHoldSince ? cc.layout(k).count(nrows, rules.S) : 0;
    estimate[k] = static_cast<double>((*heads)[k].size()) +
                  static_cast<double>(p.bits[k] + kEstimateBitsPerSample * samples) / 8;
  }
  auto trial = [&](size_t k, size_t bound) {
    IntEncoder coder(analog::kAnalogContexts);
    start_models(version, &coder);
    IntEncoder::Cursor tc = coder.cursor();
    const size_t fixed = (*heads)[k].size() + 1;
    const size_t limit = bound == SIZE_MAX ? SIZE_MAX : bound > fixed ? bound - fixed : 0;
    if (!emit_candidate(cc, p, k, version, &tc, limit)) return SIZE_MAX;
    coder.commit(tc);
    return (*heads)[k].size() + coder.finish().size();
  };
  return analog::pick_smallest(estimate, trial, kTrialMargin);
}

}  // namespace

std::vector<uint8_t> encode_analog_window(const double* rows, size_t nrows, int channels,
                                          const AnalogHints& hints, size_t repeat_S,
                                          FormatVersion format) {
  const int version = window_version(format);
  const analog::HeaderRules rules = header_rules(format, repeat_S);
  ByteWriter head;
  analog::HeaderState state;  // the last constant; from 9.2 on the last scaling (FORMAT.md 11.7)
  bool any_coded = false;
  IntEncoder ent(analog::kAnalogContexts);
  start_models(version, &ent);
  IntEncoder::Cursor cur = ent.cursor();
  const size_t nch = static_cast<size_t>(std::max(channels, 0));
  EarlierChannels earlier(nch);
  // Channel-major copy of the window, read row by row: one channel's samples are then
  // contiguous (a column of the row-major window is one cache line per sample).
  std::vector<double> cols(nch * nrows);
  for (size_t i = 0; i < nrows; ++i)
    for (size_t c = 0; c < nch; ++c) cols[c * nrows + i] = rows[i * nch + c];
  for (int c = 0; c < channels; ++c) {
    analog::ChannelHint hint =
        static_cast<size_t>(c) < hints.channel.size() ? hints.channel[c] : analog::ChannelHint();
    hint.share = state.share;  // empty before 9.2 (never set)
    const ChannelCandidates cc = channel_candidates(cols.data() + static_cast<size_t>(c) * nrows,
                                                    nrows, repeat_S, hint, format);
    CandidatePlans plans = plan_candidates(cc, earlier, c, format);
    size_t pick = 0;
    if (cc.reprs.size() > 1) {
      std::vector<std::vector<uint8_t>> heads;
      std::vector<analog::HeaderState> states;
      pick = pick_candidate(cc, plans, rules, state, nrows, format, &heads, &states);
      head.bytes(heads[pick]);  // the header written for its estimate, from the same state
      state = states[pick];
    } else {
      analog::write_repr_header(cc.reprs[0], cc.layout(0), rules, &state, &head);
    }
    const Kind kind = cc.reprs[pick].kind;
    any_coded |= coded(kind);
    emit_candidate(cc, plans, pick, version, &cur, SIZE_MAX);
    earlier.layouts[c] = cc.layout(pick);
    earlier.has_r1[c] = analog::is_integer_kind(kind);
    if (earlier.has_r1[c]) {
      earlier.r1s[c] = std::move(plans.ints[pick].r1);
      earlier.energy[c] = analog::reference_energy(earlier.r1s[c]);
    }
  }
  ent.commit(cur);
  ByteWriter out;
  out.u8(static_cast<uint8_t>(version));
  out.varint(head.size());
  out.bytes(head.buffer());
  if (any_coded) out.bytes(ent.finish());
  return std::move(out.buffer());
}

void decode_analog_window(const uint8_t* data, size_t size, size_t nrows, int channels,
                          double* rows, const std::string& what, size_t repeat_S,
                          FormatVersion format) {
  const bool format9 = format >= kAnalogFloat9Since, format91 = format >= kAnalogConstantSince;
  const analog::HeaderRules rules = header_rules(format, repeat_S);
  ByteReader in(data, size, what);
  const int version = in.u8();
  if (version > window_version(format))
    throw Error(ErrorCode::kCorrupt, what + ": unknown analog window version");
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
    if (layouts[c].all()) {
      analog::reconstruct(reprs[c], nrows, rows + c, nch, what);
      return;
    }
    tmp.resize(kept[c]);
    analog::reconstruct(reprs[c], kept[c], tmp.data(), 1, what);
    layouts[c].expand(tmp.data(), nrows, repeat_S, rows + c, nch, what);
  };
  if (!any_coded) {
    if (!in.at_end())
      throw Error(ErrorCode::kCorrupt, what + ": analog window has bytes left over");
    for (size_t c = 0; c < nch; ++c) put(c);
    return;
  }
  IntDecoder ent(data + in.offset(), in.remaining(), analog::kAnalogContexts, what);
  start_models(version, &ent);
  IntDecoder::Cursor cur = ent.cursor();
  std::vector<std::vector<int32_t>> r1s(nch);
  std::vector<bool> has_r1(nch, false);
  for (size_t c = 0; c < nch; ++c) {
    ChannelRepr& r = reprs[c];
    if (analog::is_integer_kind(r.kind)) {
      std::vector<bool> use(nch, false);  // the same kept rows (FORMAT.md 11.3, 11.4, 11.5)
      for (size_t j = 0; j < c; ++j) use[j] = has_r1[j] && layouts[j] == layouts[c];
      decode_int_channel(kept[c], cross_refs(r1s, use, static_cast<int>(c)), format91, version,
                         &cur, &r.ints, &r1s[c]);
      has_r1[c] = true;
    } else if (r.kind == Kind::kFloat32 || r.kind == Kind::kFloat64)
      analog::decode_float_channel(kept[c], r.kind == Kind::kFloat32, &cur, &r.filled, format9);
    put(c);
    std::vector<int32_t>().swap(r.ints);
    std::vector<double>().swap(r.filled);
  }
  ent.commit(cur);
  if (!ent.at_end())
    throw Error(ErrorCode::kCorrupt, what + ": analog samples have bytes left over");
}

}  // namespace capz
