// The scan geometry encoder (docs/FORMAT.md "Scans (format 1.1)").
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/scan_geometry.h"
#include "coding/scan_raster.h"
#include "coding/scan_shared.h"
#include "coding/scan_table.h"
#include "coding/scan_trial_gates.h"
#include "coding/scan_trial_sinks.h"

namespace capz {

namespace {

using namespace scan_sinks;  // NOLINT: the encoder's own sinks (scan_trial_sinks.h)

uint8_t validity(const ScanGeometry& g, size_t first, size_t n) {
  size_t v = 0;
  for (size_t i = first; i < first + n; ++i) v += g.valid[i] != 0;
  return v == n ? scan::kAllValid : v == 0 ? scan::kNoneValid : scan::kSomeValid;
}

// A frame's Cartesian estimate from a state: the same under every table (Cartesian coding reads
// only st.last and st.last_bits), so kept for the next table's pass over the window.
struct CartesianEstimate {
  bool known = false;
  int32_t last[3] = {0, 0, 0};
  int last_bits[3] = {0, 0, 0};
  double bits = 0;
  uint64_t symbols = 0;
  bool same_state(const scan::State& st) const {
    return known && std::equal(last, last + 3, st.last) &&
           std::equal(last_bits, last_bits + 3, st.last_bits);
  }
};

// A frame's spherical trial: its symbols (the first `syms` of sym_room), the hypotenuse's
// alternatives to the second of x y, and their tallies.
struct Trial {
  Room<Sym> sym_room;
  Room<AltSym> alt_room;
  size_t syms = 0;
  Tally tally, azimuth, hypot;
  const Sym* begin() const { return sym_room.data(); }
  const Sym* end() const { return sym_room.data() + syms; }
};

// Scratch of the per-frame choice, kept across frames and tables.
struct Scratch {
  std::vector<int32_t> q;
  std::vector<uint8_t> v;
  Trial trial, walk_trial;  // the spherical trial of the frame; with the ring walk
  int walk = -1;            // the window's choice of the ring walk (code_chosen): -1 not made yet
  int pairs = -1;           // the window's choice of ring pair frames (code_chosen), every table's
  std::vector<double> log_t, log_c;     // Tally::estimate's prefix sums
  std::vector<CartesianEstimate> cart;  // per frame of the window
  std::vector<int8_t> spherical_ok;     // per frame: scan::spherical_ok, -1 not yet known
  std::shared_ptr<scan::SweepMaps> maps = std::make_shared<scan::SweepMaps>();   // every table's
  std::shared_ptr<scan::SweepMaps> spare = std::make_shared<scan::SweepMaps>();  // a kept coding's
  size_t record_limit = ScanWorkspace::kRecordLimit;
  bool successors = false;  // a window before kept the previous sweep's successors
};

// Whether spherical coding (its symbols recorded in s->trial, tallied in its tally) costs less than
// Cartesian by CostSink, the exact estimate. Decided on Tally::estimate when the two differ by
// more than both estimates' rounding can move them (N terms each below 2^6, summed in binary64:
// at most N (2^-52 sum + 2^-46) apart in all, with room to spare); else by CostSink itself.
bool spherical_wins(const scan::State& st, uint8_t flags, uint8_t coded, const ScanGeometry& g,
                    const scan::Placement& placed, size_t f, size_t first, size_t n, Scratch* s) {
  CartesianEstimate& c = s->cart[f];
  const double sph = s->trial.tally.estimate(&s->log_t, &s->log_c);
  if (!c.same_state(st)) {
    // Cartesian coding's raw bits alone bound its estimate from below (every symbol's token
    // costs more than 0 bits): when the spherical estimate is under that bound by twice the
    // margin below (taken for 4 symbols a point, Cartesian coding's most), the estimate would
    // have chosen spherical as well.
    const double terms = static_cast<double>(s->trial.tally.symbols() + 4 * n) + 2.0 * 64 * 64;
    const double margin = 4.0 * terms * (terms * 64.0 * 0x1p-52 + 0x1p-46);
    if (sph < static_cast<double>(cartesian_raw_bits(st, g, first, n)) - 2 * margin) return true;
    Tally tally;
    EncodeIo<Tally> io(&tally, g, placed);
    scan::State trial = st.trial();
    scan::code_points(io, trial, flags, first, n, s->q.data(), s->v.data());
    c.known = true;
    std::copy(st.last, st.last + 3, c.last);
    std::copy(st.last_bits, st.last_bits + 3, c.last_bits);
    c.bits = tally.estimate(&s->log_t, &s->log_c);
    c.symbols = tally.symbols();
  }
  const double terms = static_cast<double>(s->trial.tally.symbols() + c.symbols) + 2.0 * 64 * 64;
  const double margin = 4.0 * terms * (terms * 64.0 * 0x1p-52 + 0x1p-46);
  if (sph < c.bits - margin) return true;
  if (sph > c.bits + margin) return false;
  CostSink exact_sph, exact_cart;
  if (s->trial.syms > 0 || n == 0) {
    for (const Sym& y : s->trial) exact_sph.put(y.u, static_cast<int>(y.ctx));
  } else {  // a frame too large to record (code_chosen): its trial coded again, counted
    EncodeIo<CostSink> sph_io(&exact_sph, g, placed);
    scan::State again = st.trial();
    scan::code_points(sph_io, again, coded, first, n, s->q.data(), s->v.data());
  }
  EncodeIo<CostSink> io(&exact_cart, g, placed);
  scan::State trial = st.trial();
  scan::code_points(io, trial, flags, first, n, s->q.data(), s->v.data());
  return exact_sph.bits < exact_cart.bits;
}

// The spherical trial of frame [first, first + n) under *flags on a staged copy of *st (a
// trial copy for a window's last frame, whose map no later sweep reads; returned), its symbols
// recorded in *t (room for `room` of them) and tallied in t->tally, the second of x y by the
// cheaper of the azimuth and the hypotenuse by the estimate (both coded in the one pass: the choice
// moves no other symbol). Sets kHypot in *flags when the hypotenuse's. Without `record` its
// symbols are only tallied (t->syms 0).
scan::State spherical_trial(const scan::State& st, bool last, uint8_t* flags, const ScanGeometry& g,
                            const scan::Placement& placed, size_t first, size_t n, size_t room,
                            Trial* t, Scratch* s, bool record = true) {
  scan::State staged = last ? st.trial() : st.staged();
  t->tally.clear();
  t->azimuth.clear();
  t->hypot.clear();
  Sym* syms = nullptr;
  AltSym *alts = nullptr, *alts_end = nullptr;
  t->syms = 0;
  if (record) {
    syms = t->sym_room.reserve(room);
    alts = t->alt_room.reserve(n);
    RecordSink rec{syms, syms, syms + room, alts, &t->tally, &t->azimuth, &t->hypot};
    RecordIo io(&rec, g, placed);
    scan::code_points(io, staged, *flags, first, n, s->q.data(), s->v.data());
    t->syms = static_cast<size_t>(rec.next - rec.syms);
    alts_end = rec.alt;
  } else {
    TallySink tally{&t->tally, &t->azimuth, &t->hypot};
    TallyIo io(&tally, g, placed);
    scan::code_points(io, staged, *flags, first, n, s->q.data(), s->v.data());
  }
  const bool hypot =
      t->hypot.estimate(&s->log_t, &s->log_c) < t->azimuth.estimate(&s->log_t, &s->log_c);
  if (hypot) {
    for (const AltSym* y = alts; y != alts_end; ++y) syms[y->at] = y->sym;
    *flags = static_cast<uint8_t>(*flags | scan::kHypot);
  }
  t->tally.add(hypot ? t->hypot : t->azimuth);
  return staged;
}

// Codes frame f spherically when that costs less by the estimate, else Cartesian: the spherical
// coding runs once, on a staged state, its symbols recorded, and is replayed into the block
// when it wins. Returns the frame's flags as coded. The window's last frame (f + 1 = its
// frames) is coded on trial states: no later sweep reads the map it would write (the map never
// changes a symbol of its own sweep), so its cells are not touched.
uint8_t code_chosen(IntEncoder* enc, scan::State* st, uint8_t flags, const ScanGeometry& g,
                    const scan::Placement& placed, size_t f, size_t first, size_t n, Scratch* s) {
  const auto sph = static_cast<uint8_t>(flags | scan::kSpherical);
  size_t passed = 0;
  const bool upward = walk_worth_trying(g, placed.polar, st->table().rings(), first, n, &passed);
  const bool last = f + 1 == g.counts.size();
  // At most 7 symbols a point; a walk frame's ring takes the repeat flag and the rings passed.
  const size_t room = 7 * n + (upward ? n + passed : 0) + 1;
  auto coded = static_cast<uint8_t>(upward && s->walk == 1 ? sph | scan::kRingWalk
                                    : s->pairs == 1        ? sph | scan::kRingPairs
                                                           : sph);
  const bool record = n <= s->record_limit;  // (ScanWorkspace::record_limit)
  scan::State staged =
      spherical_trial(*st, last, &coded, g, placed, first, n, room, &s->trial, s, record);
  // Codes the frame with `bit` as well (into the spare trial) and keeps the smaller: *choice.
  auto try_also = [&](uint8_t bit, int* choice) {
    auto other = static_cast<uint8_t>(sph | bit);
    scan::State kept =
        spherical_trial(*st, last, &other, g, placed, first, n, room, &s->walk_trial, s, record);
    *choice = s->walk_trial.tally.estimate(&s->log_t, &s->log_c) <
              s->trial.tally.estimate(&s->log_t, &s->log_c);
    if (*choice == 1) {
      std::swap(s->trial, s->walk_trial);
      staged = std::move(kept);
      coded = other;
    }
  };
  // The window's first frame whose rings run upward is coded both ways (both write the same
  // ranges into this sweep's map), the smaller kept; the window's later frames follow it.
  if (upward && s->walk < 0) try_also(scan::kRingWalk, &s->walk);
  // The window's first frame coded without the walk tries ring pair frames when they look
  // worth it (the trial of the walk's room), the smaller kept; the window's later frames follow.
  if (!(coded & scan::kRingWalk) && s->pairs < 0) {
    s->pairs = 0;
    if (pairs_worth_trying(g, placed.polar, *st, first, n)) try_also(scan::kRingPairs, &s->pairs);
  }
  if (spherical_wins(*st, flags, coded, g, placed, f, first, n, s)) {
    if (record) {
      IntEncoder::Cursor c = enc->cursor();
      for (const Sym& y : s->trial) scan::put_value(c, y.u, static_cast<int>(y.ctx));
      enc->commit(c);
    } else {  // coded again, as the trial did (the map's cells written again, the same)
      st->clear_sweep();
      staged = last ? st->trial() : st->staged();
      PutSink put{enc};
      EncodeIo<PutSink> io(&put, g, placed);
      scan::code_points(io, staged, coded, first, n, s->q.data(), s->v.data());
    }
    *st = staged;
    st->end_frame();
    return coded;
  }
  st->clear_sweep();
  PutSink put{enc};
  EncodeIo<PutSink> direct(&put, g, placed);
  scan::code_frame(direct, *st, flags, first, n, s->q.data(), s->v.data());
  return flags;
}

// A window's coding under one table, frame by frame: the block so far, the state after it and
// the frames' flags. (The encoder points into itself and the state at its table: neither moves.)
struct Coding {
  Coding(const scan::Table& t, std::shared_ptr<scan::SweepMaps> maps)
      : enc(new IntEncoder(scan::kContexts)), st(new scan::State(t, std::move(maps))) {
    enc->add_bit_models();
  }
  std::unique_ptr<IntEncoder> enc;
  std::unique_ptr<scan::State> st;
  std::vector<uint8_t> flags;
  std::vector<int32_t> turns;    // per frame its turn (FORMAT.md "Turns")
  size_t frames = 0, first = 0;  // the frames coded, their points
  int walk = -1;                 // its ring walk choice (Scratch::walk)
};

// Codes frames c->frames .. to - 1 of g: per frame the cheaper of spherical and Cartesian coding.
void code_frames(const ScanGeometry& g, const scan::Placement& placed, size_t to, Coding* c,
                 Scratch* s) {
  const scan::Table& t = c->st->table();
  PutSink sink{c->enc.get()};
  EncodeIo<PutSink> io(&sink, g, placed);
  s->cart.resize(g.counts.size());
  s->spherical_ok.resize(g.counts.size(), -1);
  c->flags.resize(to);
  c->turns.resize(to);
  s->walk = c->walk;  // the coding's ring walk choice (code_chosen)
  for (size_t f = c->frames; f < to; ++f) {
    const size_t n = g.counts[f], first = c->first;
    s->q.resize(3 * n);
    s->v.resize(n);
    uint8_t& flags = c->flags[f];
    flags = validity(g, first, n);
    int8_t& ok = s->spherical_ok[f];  // the same under every table
    if (t.rings() > 0 && flags != scan::kNoneValid && ok < 0) ok = scan::spherical_ok(g, first, n);
    const bool sph = t.rings() > 0 && flags != scan::kNoneValid && ok;
    // A frame after the window's first is lined up with the previous sweep's map (FORMAT.md
    // "Turns").
    c->turns[f] = sph && f > 0 ? find_turn(g, placed.polar, *c->st, first, n) : 0;
    c->st->set_turn(c->turns[f]);
    if (sph) {
      flags = code_chosen(c->enc.get(), c->st.get(), flags, g, placed, f, first, n, s);
    } else {
      scan::code_frame(io, *c->st, flags, first, n, s->q.data(), s->v.data());
    }
    c->first += n;
    c->frames = f + 1;
  }
  c->walk = s->walk;
}

// The payload of c's frames (g's first c->frames) under c's table; c's block is finished.
std::vector<uint8_t> finish(const ScanGeometry& g, Coding* c) {
  ScanGeometry head;  // write_header reads the counts only
  head.counts.assign(g.counts.begin(), g.counts.begin() + static_cast<std::ptrdiff_t>(c->frames));
  std::vector<uint8_t> out;
  scan::write_header(head, c->flags, c->st->table(), &out, &c->turns);
  const std::vector<uint8_t> body = c->enc->finish();
  out.insert(out.end(), body.begin(), body.end());
  return out;
}

// finish(g, c)'s size, c left as it is.
size_t finished_size(const ScanGeometry& g, const Coding& c) {
  ScanGeometry head;
  head.counts.assign(g.counts.begin(), g.counts.begin() + static_cast<std::ptrdiff_t>(c.frames));
  std::vector<uint8_t> out;
  scan::write_header(head, c.flags, c.st->table(), &out, &c.turns);
  return out.size() + c.enc->finished_size();
}

// The payload under one table.
std::vector<uint8_t> encode_with(const ScanGeometry& g, const scan::Table& t,
                                 const scan::Placement& placed, Scratch* s) {
  Coding c(t, s->maps);
  code_frames(g, placed, g.counts.size(), &c, s);
  return finish(g, &c);
}

// A table to try: the azimuth step found divided by `divisor` (0: the azimuths' quantum), ranges
// in the sensor's steps or not.
struct TableChoice {
  double divisor;
  bool units;
};

// The choices (of `tried`, in order) whose table codes g's first kTrialFrames frames alone
// within kTrialSlack of the smallest payload. On robosense-helios16p at 1 mm the first frame
// alone ranked the tables otherwise than the window (the map of the sweep before counts), two
// frames 1.8 % apart where the window's were 1.1 % apart; with the second of x y chosen per
// frame (flags_f bit 6), its two frames put the step divided by 4 3.0 % behind the step as
// found, whose window came out 0.5 % larger. *tables: the tables tried (each the window's; only
// the first frames' points placed). *kept: the coding of the first frames under the first
// table of the smallest payload (a choice: the window's coding under it goes on from there),
// its maps s->spare's, which it swaps with s->maps.
constexpr double kTrialSlack = 1.03;
constexpr size_t kTrialFrames = 2;
std::vector<TableChoice> first_frame_choice(const ScanGeometry& g, const scan::RingFit& fit,
                                            const std::vector<TableChoice>& tried,
                                            std::vector<scan::Table>* tables,
                                            scan::Placement* placed, std::unique_ptr<Coding>* kept,
                                            Scratch* s) {
  const size_t n = g.counts[0] + g.counts[1];
  tables->reserve(tried.size());  // the codings point at their tables
  std::vector<size_t> sizes;
  for (const TableChoice& c : tried) {
    tables->push_back(
        scan::table_fit(fit, c.divisor, c.units, tables->empty() ? nullptr : &tables->back()));
    const scan::Table& t = tables->back();
    scan::place_points(g, fit, t, n, placed);
    std::unique_ptr<Coding> coding(new Coding(t, s->maps));
    code_frames(g, *placed, kTrialFrames, coding.get(), s);
    sizes.push_back(finished_size(g, *coding));
    if (sizes.size() == 1 || sizes.back() < *std::min_element(sizes.begin(), sizes.end() - 1)) {
      kept->swap(coding);
      std::swap(s->maps, s->spare);  // the kept coding's maps are not reset by the next table
    }
    if (t.rings() == 0) break;
  }
  s->cart.clear();  // its estimates were of the first frame's state under the last table
  const double least = static_cast<double>(*std::min_element(sizes.begin(), sizes.end()));
  std::vector<TableChoice> out;
  for (size_t i = 0; i < sizes.size(); ++i)  // a size an earlier table had: the same coding, likely
    if (static_cast<double>(sizes[i]) <= least * kTrialSlack &&
        std::find(sizes.begin(), sizes.begin() + static_cast<std::ptrdiff_t>(i), sizes[i]) ==
            sizes.begin() + static_cast<std::ptrdiff_t>(i))
      out.push_back(tried[i]);
  return out;
}

// The size of the trial sample's payload (trial_sample, drawn as `from`) under table t. `apart`:
// between codings of the window, whose frames' estimates and checks are set aside around it.
size_t sample_size(const ScanGeometry& g, const ScanGeometry& sample,
                   const std::vector<size_t>& from, const scan::RingFit& fit, const scan::Table& t,
                   Scratch* s, bool apart = false) {
  if (apart) s->cart.clear(), s->spherical_ok.clear();
  scan::Placement all, placed;
  scan::Table u = t;  // (with the successors once a window kept them: sizes of one kind)
  u.successors = u.successors || s->successors;
  scan::place_points(g, fit, u, from.back() + 1, &all);
  placed.polar.resize(from.size());
  for (size_t j = 0; j < from.size(); ++j) placed.polar[j] = all.polar[from[j]];
  if (!all.fire.empty()) {
    placed.fire.resize(from.size());
    for (size_t j = 0; j < from.size(); ++j) placed.fire[j] = all.fire[from[j]];
  }
  Coding coding(u, s->maps);
  code_frames(sample, placed, sample.counts.size(), &coding, s);
  if (apart) s->cart.clear(), s->spherical_ok.clear();
  return finished_size(sample, coding);
}

// The choices (of `tried`, in order) whose table codes the window's trial sample within
// kSampleSlack of the smallest payload: what first_frame_choice does on whole frames, for
// windows whose first frames are larger than their sample. *tables: the tables tried (each the
// window's; one of an empty table per choice not tried). *sizes: the sample's payload per choice
// (0: not tried). With a choice remembered from the windows before (ws->remember, ws->choice)
// among this window's tables (a choice of the finest table, the step divided by 16 or the
// azimuths' quantum, which a window finds or not, only while the finest is the same kind),
// only that table codes the sample first, and it alone is kept when its payload is within
// kRememberSlack of what it was in the window whose trial chose it (bits a point of the sample).
constexpr double kSampleSlack = 1.03, kRememberSlack = 1.05;
std::vector<TableChoice> sampled_choice(const ScanGeometry& g, const ScanGeometry& sample,
                                        const std::vector<size_t>& from, const scan::RingFit& fit,
                                        const std::vector<TableChoice>& tried, ScanWorkspace* ws,
                                        std::vector<scan::Table>* tables,
                                        std::vector<size_t>* sizes, Scratch* s) {
  sizes->assign(tried.size(), 0);
  tables->assign(tried.size(), scan::Table());
  const auto k =
      static_cast<size_t>(std::find_if(tried.begin(), tried.end(),
                                       [&](const TableChoice& c) {
                                         return ws && ws->remember && ws->choice.bits > 0 &&
                                                (ws->choice.divisor != ws->choice.finest ||
                                                 ws->choice.finest == tried.back().divisor) &&
                                                c.divisor == ws->choice.divisor &&
                                                c.units == ws->choice.units;
                                       }) -
                          tried.begin());
  if (k < tried.size()) {
    (*tables)[k] = scan::table_fit(fit, tried[k].divisor, tried[k].units);
    (*sizes)[k] = sample_size(g, sample, from, fit, (*tables)[k], s);
    ++ws->sample_codings;
    const double bits =
        8.0 * static_cast<double>((*sizes)[k]) / static_cast<double>(sample.total());
    if (bits <= ws->choice.bits * kRememberSlack) return {tried[k]};
  }
  // Table i's sample payload (when not k's, coded already); false when it has no rings. (twin:
  // a table of the same step, whose azimuth offsets it takes, or any other: table_fit.)
  const auto code = [&](size_t i, const scan::Table* twin) {
    scan::Table& t = (*tables)[i];
    if (i != k) {
      t = scan::table_fit(fit, tried[i].divisor, tried[i].units, twin);
      (*sizes)[i] = sample_size(g, sample, from, fit, t, s);
      if (ws) ++ws->sample_codings;
    }
    return t.rings() > 0;
  };
  if (fit.unit.empty()) {  // one choice a divisor
    for (size_t i = 0; i < tried.size() && code(i, i ? &(*tables)[i - 1] : nullptr); ++i) {
    }
  } else {
    // Ranges in the sensor's steps (the second of each divisor's pair) first, then in grid units
    // with the divisor whose sample was smallest in steps, alone: in steps the sample came out
    // smaller on 171 of 177 pairs traced (16 inputs at 1 mm and 1 cm, in the file's order and
    // any), and grid units were the smallest only on robosense-e1 at 1 mm, 0.01 % below the same
    // divisor in steps (docs/lab/2026-11-30-encoder-speed-2.md).
    size_t best = tried.size();
    bool rings = true;
    for (size_t i = 1; i < tried.size() && rings; i += 2) {
      rings = code(i, &(*tables)[i - 1]);
      if (best == tried.size() || (*sizes)[i] < (*sizes)[best]) best = i;
    }
    if (rings) code(best - 1, &(*tables)[best]);
  }
  size_t least = 0;
  for (size_t v : *sizes)
    if (v > 0 && (least == 0 || v < least)) least = v;
  std::vector<TableChoice> out;
  for (size_t i = 0; i < sizes->size();
       ++i) {  // a size an earlier table had: likely the same coding
    const size_t v = (*sizes)[i];
    if (v > 0 && static_cast<double>(v) <= static_cast<double>(least) * kSampleSlack &&
        std::find(sizes->begin(), sizes->begin() + static_cast<std::ptrdiff_t>(i), v) ==
            sizes->begin() + static_cast<std::ptrdiff_t>(i))
      out.push_back(tried[i]);
  }
  return out;
}

// Table t (the best's with units bit 7 or the more byte's bit 1) tried: *best replaced when smaller
// (true), first on the trial sample when its size under the best table is known (*sampled > 0,
// then t's if kept); *ratio: t's sample over *sampled (0: not sampled).
bool try_table(const ScanGeometry& g, const ScanGeometry& sample, const std::vector<size_t>& from,
               const scan::RingFit& fit, const scan::Table& t, size_t* sampled,
               std::vector<uint8_t>* best, Scratch* s, double* ratio) {
  *ratio = 0;
  size_t size = 0;
  if (*sampled > 0) {
    size = sample_size(g, sample, from, fit, t, s, true);
    *ratio = static_cast<double>(size) / static_cast<double>(*sampled);
    if (size >= *sampled) return false;
  }
  scan::Placement placed;
  scan::place_points(g, fit, t, g.total(), &placed);
  std::vector<uint8_t> out = encode_with(g, t, placed, s);
  if (out.size() >= best->size()) return false;
  best->swap(out);
  if (*sampled > 0) *sampled = size;
  return true;
}

// How much larger units bit 7 made the last window's sample for a remembered table not to try it.
constexpr double kBeforeLost = 1.002;

// The payload of window g under the rings of `fit` (fit_rings of g and hints).
std::vector<uint8_t> encode_fitted(const ScanGeometry& g, const scan::RingFit& fit,
                                   ScanWorkspace* ws) {
  // The table's azimuth step as found, and finer ones for azimuths off that step, each with
  // ranges in grid units and, when the sensor's range step is found, in that step: the smallest
  // payload wins. In a window of more than kTrialFrames frames, only the tables whose payload for
  // the first kTrialFrames frames is within kTrialSlack of the smallest such payload code the
  // whole window.
  Scratch scratch;
  if (ws) {  // the maps of the windows before (reset for each table: the same coding)
    scratch.record_limit = ws->record_limit;
    scratch.successors = ws->remember && ws->successors;
    if (!ws->maps) ws->maps = std::make_shared<scan::SweepMaps>();
    if (!ws->spare) ws->spare = std::make_shared<scan::SweepMaps>();
    scratch.maps = ws->maps;
    scratch.spare = ws->spare;
  }
  scan::Placement placed;
  std::vector<TableChoice> tried;
  // Azimuths on the sensor's own quantum (divisor 0: the quantum's table, with the column's
  // third candidate) take the place of the finest step: tried as well, the finest step won only
  // on hesai-xt32's sorted order, by 0.04 % (docs/lab/2026-11-29-any-1mm.md).
  for (double divisor : {1.0, 4.0, fit.quantum > 0 ? 0.0 : 16.0}) {
    tried.push_back({divisor, false});
    if (!fit.unit.empty()) tried.push_back({divisor, true});
  }
  std::vector<TableChoice> choices = tried;
  std::vector<scan::Table> tables;  // of the choices tried on the first frames, in order
  std::unique_ptr<Coding> kept;     // the first frames' coding under one of them
  std::vector<size_t> from;
  const ScanGeometry sample = trial_sample(g, kTrialFrames, &from);
  size_t trial_points = 0;  // the points of the frames sampled
  for (size_t f = 0; f < sample.counts.size(); ++f) trial_points += g.counts[f];
  const bool every = ws && ws->every_table;
  std::vector<size_t> sizes;  // the sample's payloads (sampled_choice)
  if (!every && fit.rings() > 0 && sample.total() < trial_points) {
    choices = sampled_choice(g, sample, from, fit, tried, ws, &tables, &sizes, &scratch);
    // The sample's frames' Cartesian estimates and checks, kept from table to table (the same
    // frames, and an estimate is used only in the state it was made in), are not the window's.
    scratch.cart.clear();
    scratch.spherical_ok.clear();
  } else if (!every && g.counts.size() > kTrialFrames) {
    choices = first_frame_choice(g, fit, tried, &tables, &placed, &kept, &scratch);
  }
  std::vector<uint8_t> best;
  ScanChoice chosen;       // the choice of the smallest payload, when it was tried on the sample
  scan::Table t;           // the table of the choice before, then this one's
  scan::Table best_table;  // the smallest payload's
  size_t best_sample = 0;  // its sample's payload (0: not known)
  // The previous sweep's successors (FORMAT.md): on once a window of the sequence kept them, else
  // tried on the trial sample under its smallest table, or without a sample after the coding.
  bool successors = ws && ws->remember && ws->successors && !kept, decided = successors;
  size_t least = 0;  // the table of the smallest sample (sizes: 0 for a table not tried)
  for (size_t j = 0; j < sizes.size(); ++j)
    if (sizes[j] > 0 && (sizes[least] == 0 || sizes[j] < sizes[least])) least = j;
  if (!successors && !kept && g.counts.size() > 1 && !sizes.empty() && sizes[least] > 0) {
    scan::Table with = tables[least];
    with.successors = true;
    const size_t size = with.rings() ? sample_size(g, sample, from, fit, with, &scratch, true) : 0;
    successors = size > 0 && size < sizes[least];
    if (successors) sizes[least] = size, scratch.successors = true;  // (sizes compared from here)
    decided = true;
  }
  for (const TableChoice& c : choices) {
    const auto k =
        static_cast<size_t>(std::find_if(tried.begin(), tried.end(),
                                         [&](const TableChoice& o) {
                                           return o.divisor == c.divisor && o.units == c.units;
                                         }) -
                            tried.begin());
    if (k < tables.size())
      t = tables[k];
    else
      t = scan::table_fit(fit, c.divisor, c.units, &t);
    t.successors = successors;
    scan::place_points(g, fit, t, g.total(), &placed);
    std::vector<uint8_t> out;
    if (kept && &kept->st->table() == &tables[k]) {  // its first frames coded already
      code_frames(g, placed, g.counts.size(), kept.get(), &scratch);
      out = finish(g, kept.get());
      kept.reset();
    } else {
      out = encode_with(g, t, placed, &scratch);
    }
    if (ws) ++ws->tables_coded;
    if (best.empty() || out.size() < best.size()) {
      best.swap(out);
      best_table = t;
      best_sample = k < sizes.size() ? sizes[k] : 0;
      if (k < sizes.size() && sizes[k] > 0)
        chosen = {c.divisor, c.units,
                  8.0 * static_cast<double>(sizes[k]) / static_cast<double>(sample.total()),
                  tried.back().divisor};
    }
    if (t.rings() == 0) break;
  }
  // The window's choice remembered when its trial coded every table (choices.size() > 1 or a
  // sample size of another table known).
  if (ws && ws->remember &&
      std::count_if(sizes.begin(), sizes.end(), [](size_t v) { return v > 0; }) > 1)
    ws->choice = chosen;
  // Units bit 7 is not tried on a window whose table is the one remembered (its sample alone
  // coded) when it made the last window's sample where it was tried larger by more than
  // kBeforeLost: the 20-sweep pandar64 folder's every window by 0.3 % at 1 mm.
  const bool remembered =
      ws && ws->remember &&
      std::count_if(sizes.begin(), sizes.end(), [](size_t v) { return v > 0; }) == 1;
  double ratio = 0;
  if (best_table.rings() > 0 && !(remembered && best_sample > 0 && ws->before > kBeforeLost)) {
    scan::Table with = best_table;
    with.before = true;
    if (try_table(g, sample, from, fit, with, &best_sample, &best, &scratch, &ratio))
      best_table.before = true;
    if (ws && ws->remember && ratio > 0) ws->before = ratio;
  }
  // The successors of a window without a trial sample: tried after its coding.
  if (!decided && best_table.rings() > 0 && g.counts.size() > 1 && has_pair_frames(best)) {
    best_table.successors = true;
    successors = try_table(g, sample, from, fit, best_table, &best_sample, &best, &scratch, &ratio);
  }
  if (ws && ws->remember && successors) ws->successors = true;
  return best;
}

// How much larger the second rings' payload was in the last window that coded it for a window of
// a sequence not to code it (encode_geometry), and how many windows in a row may skip it: on an
// Ouster-like organized sequence (its ring field the driver's) it is 3 % larger in every window,
// and each fit is about a tenth of the encode.
constexpr double kSecondLost = 1.02;
constexpr size_t kSecondSkips = 7;

// Whether window g of a sequence skips the rings found from the elevations (encode_geometry).
bool skip_second(ScanWorkspace* ws) {
  if (!ws || !ws->remember || ws->second_ratio <= kSecondLost || ws->second_skipped >= kSecondSkips)
    return false;
  ++ws->second_skipped;
  return true;
}

// Replaces *best by the payload of g under `fit` when that is smaller; whether it did.
bool keep_smaller_fit(const ScanGeometry& g, const scan::RingFit& fit, ScanWorkspace* ws,
                      std::vector<uint8_t>* best) {
  std::vector<uint8_t> out = encode_fitted(g, fit, ws);
  if (ws && ws->remember && !best->empty()) {
    ws->second_ratio = static_cast<double>(out.size()) / static_cast<double>(best->size());
    ws->second_skipped = 0;
  }
  if (out.size() >= best->size()) return false;
  best->swap(out);
  return true;
}

// Replaces *best by window g as a flash LiDAR's raster (scan_raster.h) when that is smaller (its
// coding does not depend on the rings: tried once a window, after the fits); whether it did.
// *fine_q: the decoder's integers of *best when they are not g's, else empty. Not tried again in
// a sequence whose window before had a second frame that did not repeat its first's directions
// (a spinning sensor's: the test keys every point of the first frame, 2.6 % of the 20-sweep
// pandar64 folder's encode).
bool keep_smaller_raster(const ScanGeometry& g, const ScanHints& hints, ScanWorkspace* ws,
                         std::vector<uint8_t>* best, std::vector<int32_t>* fine_q) {
  fine_q->clear();
  const bool sequence = ws && ws->remember;  // one take's windows in order
  if (sequence && ws->moving) return false;
  const size_t before = best->size();
  scan::raster::keep_smaller(g, hints, best, fine_q, sequence ? &ws->moving : nullptr);
  return best->size() < before;
}

// encode_scan_geometry's payload; *fine_q as encode_fitted's; *rings: its payload_rings.
std::vector<uint8_t> encode_geometry(const ScanGeometry& g, const ScanHints& hints,
                                     ScanWorkspace* ws, std::vector<int32_t>* fine_q,
                                     std::vector<uint16_t>* rings) {
  size_t total = 0;
  for (uint32_t n : g.counts) total += n;
  if (g.valid.size() != total || g.q.size() != 3 * total)
    fail(ErrorCode::kInternal, "scan geometry", "the points disagree with the frames' counts");
  scan::FoundRings found;  // the bow and both rings, found once for the fits and the check
  const scan::RingFit fit = scan::fit_rings(g, hints, true, true, true, &found);
  // A ring field is not always the best rings: the RoboSense Helios 16P's near points, seen
  // from the origin 35 mm off its optical centre, leave each laser's cone by their range, and
  // rings found from the elevations split a laser by range, which keeps its two returns apart
  // (docs/lab/2026-11-29-helios-at128.md). The rings from the elevations are tried too when they
  // differ, the smaller payload kept (in a sequence, not in up to kSecondSkips windows after one
  // where they were larger by kSecondLost).
  const bool both = !hints.ring.empty() && hints.elevation_rings != 0 &&
                    (hints.elevation_rings > 0 || scan::rings_differ(g, hints, &found, ws)) &&
                    !skip_second(ws);
  scan::RingFit other;
  if (both) other = scan::fit_rings(g, hints, true, true, false, &found);
  found = scan::FoundRings();  // (the window's rings twice: not held while it is coded)
  const ScanChoice before = ws ? ws->choice : ScanChoice();
  std::vector<uint8_t> best = encode_fitted(g, fit, ws);
  bool second = false;
  if (other.rings() > 0) {
    ScanChoice chosen;
    if (ws) {
      chosen = ws->choice;
      ws->choice = before;  // the second fit's trial sees the windows before as the first's did
    }
    second = keep_smaller_fit(g, other, ws, &best);
    if (ws && !second) ws->choice = chosen;
  }
  // A raster payload's rings are the first fit's (as when each fit tried the raster itself).
  if (keep_smaller_raster(g, hints, ws, &best, fine_q)) second = false;
  *rings = scan::payload_rings(g, second ? other : fit, best);
  return best;
}

}  // namespace

std::vector<uint8_t> encode_scan_geometry(const ScanGeometry& g, const ScanHints& hints,
                                          ScanWorkspace* ws) {
  std::vector<int32_t> fine_q;
  std::vector<uint16_t> rings;
  std::vector<uint8_t> out = encode_geometry(g, hints, ws, &fine_q, &rings);
  if (ws) {
    ws->fine_payload.clear();
    if (!fine_q.empty()) ws->fine_payload = out;
    ws->fine_q.swap(fine_q);
    ws->ring_payload = out;
    ws->rings.swap(rings);
  }
  return out;
}

}  // namespace capz
