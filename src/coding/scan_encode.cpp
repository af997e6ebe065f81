// The scan geometry encoder (docs/FORMAT.md "Scans (format 1.1)").
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/scan_frames_encode.h"
#include "coding/scan_geometry.h"
#include "coding/scan_raster.h"
#include "coding/scan_shared.h"
#include "coding/scan_table.h"
#include "coding/scan_trial_gates.h"
#include "coding/scan_trial_sinks.h"

namespace capz {

namespace {

using namespace scan_sinks;   // NOLINT: the encoder's own sinks (scan_trial_sinks.h)
using namespace scan_frames;  // NOLINT: a window's frames under one table (scan_frames_encode.h)

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
  s->no_walk_trial = fit.flipped;
  code_frames(sample, placed, sample.counts.size(), &coding, s);
  s->no_walk_trial = false;
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

// The scratch of one window's coding, with the maps of the windows before when ws is given (reset
// for each table: the same coding).
void attach_workspace(ScanWorkspace* ws, Scratch* s) {
  if (!ws) return;
  s->record_limit = ws->record_limit;
  s->successors = ws->remember && ws->successors;
  if (!ws->maps) ws->maps = std::make_shared<scan::SweepMaps>();
  if (!ws->spare) ws->spare = std::make_shared<scan::SweepMaps>();
  s->maps = ws->maps;
  s->spare = ws->spare;
}

// The tables encode_fitted tries: the azimuth step as found and finer ones, each with ranges in
// grid units and, when the sensor's range step is found, in that step. Azimuths on the sensor's
// own quantum (divisor 0: the quantum's table, with the column's third candidate) take the place
// of the finest step: tried as well, the finest step won only on hesai-xt32's sorted order, by
// 0.04 % (docs/lab/2026-11-29-any-1mm.md).
std::vector<TableChoice> tables_to_try(const scan::RingFit& fit) {
  std::vector<TableChoice> tried;
  for (double divisor : {1.0, 4.0, fit.quantum > 0 ? 0.0 : 16.0}) {
    tried.push_back({divisor, false});
    if (!fit.unit.empty()) tried.push_back({divisor, true});
  }
  return tried;
}

// The previous sweep's successors (FORMAT.md) tried on the trial sample under its smallest table
// (sizes: the sample's payload per table, 0 for one not tried; the smallest replaced when they
// win). True when they are kept.
bool successors_on_sample(const ScanGeometry& g, const ScanGeometry& sample,
                          const std::vector<size_t>& from, const scan::RingFit& fit,
                          const std::vector<scan::Table>& tables, std::vector<size_t>* sizes,
                          Scratch* s) {
  size_t least = 0;  // (the caller's sizes hold one above 0)
  for (size_t j = 0; j < sizes->size(); ++j)
    if ((*sizes)[j] > 0 && ((*sizes)[least] == 0 || (*sizes)[j] < (*sizes)[least])) least = j;
  scan::Table with = tables[least];
  with.successors = true;
  const size_t size = with.rings() ? sample_size(g, sample, from, fit, with, s, true) : 0;
  const bool won = size > 0 && size < (*sizes)[least];
  if (won) (*sizes)[least] = size, s->successors = true;  // (sizes compared from here)
  return won;
}

// The smallest payload of encode_fitted's tables, with its table, its sample's payload (0: not
// known) and its choice when it was tried on the sample.
struct FittedBest {
  std::vector<uint8_t> bytes;
  scan::Table table;
  size_t sample = 0;
  ScanChoice chosen;
};

// Window g coded under each of `choices` (of `tried`; tables: those fitted already, in tried's
// order; kept: the first frames' coding under one of them), the smallest kept.
FittedBest code_choices(const ScanGeometry& g, const scan::RingFit& fit, double sample_points,
                        const std::vector<TableChoice>& tried,
                        const std::vector<TableChoice>& choices,
                        const std::vector<scan::Table>& tables, const std::vector<size_t>& sizes,
                        bool successors, std::unique_ptr<Coding>* kept, ScanWorkspace* ws,
                        Scratch* s) {
  FittedBest best;
  scan::Table t;  // the table of the choice before, then this one's
  scan::Placement placed;
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
    if (*kept && &(*kept)->st->table() == &tables[k]) {  // its first frames coded already
      code_frames(g, placed, g.counts.size(), kept->get(), s);
      out = finish(g, kept->get());
      kept->reset();
    } else {
      out = encode_with(g, t, placed, s);
    }
    if (ws) ++ws->tables_coded;
    if (best.bytes.empty() || out.size() < best.bytes.size()) {
      best.bytes.swap(out);
      best.table = t;
      best.sample = k < sizes.size() ? sizes[k] : 0;
      if (k < sizes.size() && sizes[k] > 0)
        best.chosen = {c.divisor, c.units, 8.0 * static_cast<double>(sizes[k]) / sample_points,
                       tried.back().divisor};
    }
    if (t.rings() == 0) break;
  }
  return best;
}

// The payload of window g under the rings of `fit` (fit_rings of g and hints).
std::vector<uint8_t> encode_fitted(const ScanGeometry& g, const scan::RingFit& fit,
                                   ScanWorkspace* ws) {
  // The smallest payload of tables_to_try's wins. In a window of more than kTrialFrames frames,
  // only the tables whose payload for the first kTrialFrames frames is within kTrialSlack of the
  // smallest such payload code the whole window.
  Scratch scratch;
  attach_workspace(ws, &scratch);
  scan::Placement placed;
  const std::vector<TableChoice> tried = tables_to_try(fit);
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
  // The previous sweep's successors: on once a window of the sequence kept them, else tried on
  // the trial sample under its smallest table, or without a sample after the coding.
  const auto sampled = std::count_if(sizes.begin(), sizes.end(), [](size_t v) { return v > 0; });
  bool successors = ws && ws->remember && ws->successors && !kept, decided = successors;
  if (!successors && !kept && g.counts.size() > 1 && sampled > 0) {
    successors = successors_on_sample(g, sample, from, fit, tables, &sizes, &scratch);
    decided = true;
  }
  FittedBest best = code_choices(g, fit, static_cast<double>(sample.total()), tried, choices,
                                 tables, sizes, successors, &kept, ws, &scratch);
  // The window's choice remembered when its trial coded every table (choices.size() > 1 or a
  // sample size of another table known).
  if (ws && ws->remember && sampled > 1) ws->choice = best.chosen;
  // Units bit 7 is not tried on a window whose table is the one remembered (its sample alone
  // coded) when it made the last window's sample where it was tried larger by more than
  // kBeforeLost: the 20-sweep pandar64 folder's every window by 0.3 % at 1 mm.
  const bool remembered = ws && ws->remember && sampled == 1;
  double ratio = 0;
  if (best.table.rings() > 0 && !(remembered && best.sample > 0 && ws->before > kBeforeLost)) {
    scan::Table with = best.table;
    with.before = true;
    if (try_table(g, sample, from, fit, with, &best.sample, &best.bytes, &scratch, &ratio))
      best.table.before = true;
    if (ws && ws->remember && ratio > 0) ws->before = ratio;
  }
  // The successors of a window without a trial sample: tried after its coding.
  if (!decided && best.table.rings() > 0 && g.counts.size() > 1 && has_pair_frames(best.bytes)) {
    best.table.successors = true;
    successors =
        try_table(g, sample, from, fit, best.table, &best.sample, &best.bytes, &scratch, &ratio);
  }
  if (ws && ws->remember && successors) ws->successors = true;
  return std::move(best.bytes);
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
  scan::RingFit fit = scan::fit_rings(g, hints, true, true, true, &found);
  if (scan::rings_run_downward(g, fit)) scan::flip_rings(g, &fit);
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
  if (both && scan::rings_run_downward(g, other)) scan::flip_rings(g, &other);
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
