// The analog window's encoder (docs/FORMAT.md 11): per channel its candidates (representations
// of every row and of the rows a layout keeps), each candidate's plan, the pick by trial codings
// and the chosen one emitted; the decoder is analog_codec.cpp.
#include "capz/error.h"
#include "coding/analog/analog_cascade.h"
#include "coding/analog/analog_codec.h"
#include "coding/analog/analog_cross.h"
#include "coding/analog/analog_entropy.h"
#include "coding/analog/analog_float.h"
#include "coding/analog/analog_interp.h"
#include "coding/analog/analog_layout.h"
#include "coding/analog/analog_lpc.h"
#include "coding/analog/analog_pick.h"
#include "coding/analog/analog_repeat.h"
#include "coding/analog/analog_scratch.h"
#include "coding/analog/analog_window.h"
#include "coding/bytes.h"

namespace capz {
namespace {

using analog::ChannelRepr;
using analog::Kind;
using namespace analog::window;

// Candidates whose estimated size is above this times the smallest estimate are not
// trial-coded (analog::pick_smallest). On the 98 C3D takes of capz_analog_bench, 1.2 codes
// 5,273,482 bytes for the 5,273,240 of trying every candidate (5,219,447 for 5,219,153 with
// --repeats), and trial-codes about a fifth of the samples that trying all would.
constexpr double kTrialMargin = 1.2;
// What a coded sample costs beyond its residual's bit length, in the candidates' estimates: a zero
// residual has no bits of length, yet a candidate that leaves out held or repeated samples saves
// their tokens (FORMAT.md 9.4). 1 bit: 124 bytes less on the 98 shared takes than 0, the same as 2,
// at the same speed.
constexpr uint64_t kEstimateBitsPerSample = 1;

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

// The LPC stage of a whole channel: per-block parameters and the residuals x - p, where the
// first min(order, ...) samples of the window are predicted by the previous sample (0 for the
// first) and the others by the block's LPC. *tally: the residuals' tokens (token_cost_bits).
void lpc_stage(const std::vector<int32_t>& x, std::vector<analog::LpcParams>* params,
               std::vector<int32_t>* r, analog::TokenTally* tally) {
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
                                                     r->data() + b0, true, tally));
    const size_t head = std::min(b1, std::max(b0, static_cast<size_t>(params->back().order)));
    for (size_t i = b0; i < head; ++i) {
      tally->remove((*r)[i]);
      (*r)[i] = static_cast<int32_t>(x[i] - (i ? x[i - 1] : 0));
      tally->add((*r)[i]);
    }
  }
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
                      const std::vector<double>& ref_energy, IntPlan* plan) {
  analog::TokenTally r1_tokens;
  lpc_stage(x, &plan->params, &plan->r1, &r1_tokens);
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
// parameters and residuals (FORMAT.md 4.2.5, 9.5, 9.7).
// Stops, returning false, once enc->bytes_out() reaches `limit` (checked every kTrialCheck
// samples). Everything it calls is inlined (flatten) and it codes through a local copy of the
// cursor, which then stays in registers (entropy.h's Cursor).
__attribute__((flatten)) bool emit_int_channel(const IntPlan& plan, IntEncoder::Cursor* out,
                                               size_t limit = SIZE_MAX) {
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
      for (size_t i = i0; i < i1; ++i) analog::put_residual_v2(enc, &mag, plan.r[i]);
    }
  }
  *out = c;
  return true;
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
                                     const analog::ChannelHint& hint) {
  ChannelCandidates cc;
  cc.reprs = analog::candidate_representations(col, 1, nrows, hint);
  cc.layouts.resize(1);
  cc.layout_at.assign(cc.reprs.size(), 0);
  if (cc.reprs[0].kind == Kind::kConst) return cc;
  const size_t frames = repeat_S > 0 && nrows % repeat_S == 0 ? nrows / repeat_S : 0;
  analog::KeptRows more;
  if (frames) more.repeats = analog::repeated_frames(col, 1, frames, repeat_S);
  if (more.repeats.empty()) analog::find_interpolation(col, 1, nrows, &more.interp);
  // A channel held for P > 2 rows also interpolates at period 2 with exceptions around its
  // changes: the layout with fewer kept samples is offered.
  analog::Hold hold;
  if (more.repeats.empty() && analog::find_hold(col, 1, nrows, &hold) &&
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
CandidatePlans plan_candidates(const ChannelCandidates& cc, const EarlierChannels& earlier, int c) {
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
                       &p.ints[k]);
      p.bits[k] = p.ints[k].bits;
    } else if (is_float_kind(r.kind)) {
      const bool f32 = r.kind == Kind::kFloat32;
      p.floats[k] = analog::choose_float_plan9(r.filled, f32, &p.bits[k]);
    }
  }
  return p;
}

// Codes candidate k's samples; false when the coding stopped at `limit` bytes out (a trial that
// cannot win).
bool emit_candidate(const ChannelCandidates& cc, const CandidatePlans& p, size_t k,
                    IntEncoder::Cursor* enc, size_t limit) {
  const ChannelRepr& r = cc.reprs[k];
  if (analog::is_integer_kind(r.kind)) return emit_int_channel(p.ints[k], enc, limit);
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
                      size_t nrows, std::vector<std::vector<uint8_t>>* heads,
                      std::vector<analog::HeaderState>* states) {
  const size_t K = cc.reprs.size();
  std::vector<double> estimate(K);
  heads->resize(K);
  states->assign(K, state);
  for (size_t k = 0; k < K; ++k) {
    ByteWriter th;
    analog::write_repr_header(cc.reprs[k], cc.layout(k), rules, &(*states)[k], &th);
    (*heads)[k] = std::move(th.buffer());
    const uint64_t samples = cc.layout(k).count(nrows, rules.S);
    estimate[k] = static_cast<double>((*heads)[k].size()) +
                  static_cast<double>(p.bits[k] + kEstimateBitsPerSample * samples) / 8;
  }
  auto trial = [&](size_t k, size_t bound) {
    IntEncoder coder(analog::kAnalogContexts);
    analog::start_low_bit_models(&coder);
    IntEncoder::Cursor tc = coder.cursor();
    const size_t fixed = (*heads)[k].size() + 1;
    const size_t limit = bound == SIZE_MAX ? SIZE_MAX : bound > fixed ? bound - fixed : 0;
    if (!emit_candidate(cc, p, k, &tc, limit)) return SIZE_MAX;
    coder.commit(tc);
    return (*heads)[k].size() + coder.finish().size();
  };
  return analog::pick_smallest(estimate, trial, kTrialMargin);
}

}  // namespace

std::vector<uint8_t> encode_analog_window(const double* rows, size_t nrows, int channels,
                                          const AnalogHints& hints, size_t repeat_S) {
  const analog::HeaderRules rules = header_rules(repeat_S);
  ByteWriter head;
  analog::HeaderState state;  // the last constant, the last scaling (FORMAT.md 9.6)
  bool any_coded = false;
  IntEncoder ent(analog::kAnalogContexts);
  analog::start_low_bit_models(&ent);
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
    hint.share = state.share;
    const ChannelCandidates cc =
        channel_candidates(cols.data() + static_cast<size_t>(c) * nrows, nrows, repeat_S, hint);
    CandidatePlans plans = plan_candidates(cc, earlier, c);
    size_t pick = 0;
    if (cc.reprs.size() > 1) {
      std::vector<std::vector<uint8_t>> heads;
      std::vector<analog::HeaderState> states;
      pick = pick_candidate(cc, plans, rules, state, nrows, &heads, &states);
      head.bytes(heads[pick]);  // the header written for its estimate, from the same state
      state = states[pick];
    } else {
      analog::write_repr_header(cc.reprs[0], cc.layout(0), rules, &state, &head);
    }
    const Kind kind = cc.reprs[pick].kind;
    any_coded |= coded(kind);
    emit_candidate(cc, plans, pick, &cur, SIZE_MAX);
    earlier.layouts[c] = cc.layout(pick);
    earlier.has_r1[c] = analog::is_integer_kind(kind);
    if (earlier.has_r1[c]) {
      earlier.r1s[c] = std::move(plans.ints[pick].r1);
      earlier.energy[c] = analog::reference_energy(earlier.r1s[c]);
    }
  }
  ent.commit(cur);
  ByteWriter out;
  out.u8(static_cast<uint8_t>(kWindowVersion));
  out.varint(head.size());
  out.bytes(head.buffer());
  if (any_coded) out.bytes(ent.finish());
  return std::move(out.buffer());
}

}  // namespace capz
