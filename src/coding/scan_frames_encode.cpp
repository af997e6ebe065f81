// The scan geometry encoder's coding of a window's frames under one table (scan_frames_encode.h).
#include "coding/scan_frames_encode.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "capz/error.h"
#include "coding/scan_trial_gates.h"

namespace capz {
namespace scan_frames {

using namespace scan_sinks;  // NOLINT: the encoder's own sinks (scan_trial_sinks.h)

namespace {

uint8_t validity(const ScanGeometry& g, size_t first, size_t n) {
  size_t v = 0;
  for (size_t i = first; i < first + n; ++i) v += g.valid[i] != 0;
  return v == n ? scan::kAllValid : v == 0 ? scan::kNoneValid : scan::kSomeValid;
}

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
  if (upward && s->walk < 0 && !s->no_walk_trial) try_also(scan::kRingWalk, &s->walk);
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

}  // namespace

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

}  // namespace scan_frames
}  // namespace capz
