// Lossless coding of one window of per-point attribute channels (PCD fields other than x y z:
// colour, intensity, normals, labels, ...); the byte layout is docs/FORMAT.md 13 (`ATTR`).
// Every element comes back bit for bit (NaN payloads, -0.0, padding bytes included).
//
// Input: per attribute (take.h PointAttribute: type F/U/I, size, count), the window's bytes,
// frames x points x count elements of `size` bytes, little-endian. `width` is the frames' WIDTH
// (an organized cloud's row length; `points` for an unorganized one), used by the spatial
// predictors.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "capz/take.h"

namespace capz {

// One attribute's type, as META's PCD layout gives it (name, type, size, count).
using AttrSpec = PCDField;

// The attributes of a PCD layout: its fields other than x y z, in order.
std::vector<AttrSpec> attribute_specs(const std::vector<PCDField>& fields);

// True for the fields the encoder codes through the colour transform (size 4, count 1, named
// rgb or rgba).
bool is_colour_field(const AttrSpec& s);

// True when some field is a candidate for predictor 9 (FORMAT.md 6.1: float32 normal_z after
// normal_x and normal_y, or a float32 count-3 normal* field).
bool has_unit_candidate(const std::vector<AttrSpec>& specs);

// A ragged window's ATTR (FORMAT.md "Scans (format 1.1)": point fields of a ragged window): the
// attributes coded key-first and predictor 12 allowed. xyz: the window's decoded coordinates
// (points x 3, binary64, as the decoder has them), for predictor 12's range; nullptr: none.
// ring: each point's geometry ring (predictor 13: the ring the SCNW payload decoded for it,
// ScanGeometry::kNoRing for none), or nullptr when no point has one.
// q, frame_offsets, frames: the window's SCNW integers (x y z per point) and its frames' point
// offsets (frames + 1 of them), for predictor 12's sweep cells; nullptr / 0 when not given.
// trials: the encoder's memory of the stream's field trials (FieldTrials), or nullptr: every
// trial runs in every window.
// The encoder's own, carried from window to window of one ragged stream (any choice decodes):
// - lzma_rest: per field (specs' order), the windows left in which its LZMA transforms are not
//   tried, set after a window where they were tried and its predictive coding was under
//   kLzmaRestRatio of the smallest (coded or estimated);
// - near: the answer of the window's trial of predictors 10 and 11 (whether their neighbour
//   search pays), taken without the trial in the kNearRest windows after it (rest: those left).
struct FieldTrials {
  std::vector<uint8_t> lzma_rest;
  struct Near {
    uint8_t rest = 0;
    bool pays = false;
  } near;
};
struct RaggedFields {
  const double* xyz = nullptr;
  const uint16_t* ring = nullptr;
  const int32_t* q = nullptr;
  const size_t* frame_offsets = nullptr;
  size_t frames = 0;
  FieldTrials* trials = nullptr;
};
constexpr double kLzmaRestRatio = 0.9;
constexpr uint8_t kLzmaRest = 7;  // windows: the trial comes back every eighth
constexpr uint8_t kNearRest = 7;

// The ATTR payload after the window index: per attribute, its transform and data.
// valid: the window's gap mask (frames x points, from POSW / MASK), or nullptr for none (the
// decoder must be given the same). q: the window's POSW integers (frames x points x 3, as the
// decoder will have them at the valid samples), which makes predictors 10 and 11 candidates
// (FORMAT.md 7.3); nullptr: they are not tried (positions as transform output, or a choice of
// the caller's). estimate: the LZMA transforms 2 and 3 of a large field (256 KiB and more, no
// split by the mask) are first coded on its first eighth, and only the one whose estimate is
// smaller is coded in full, none when the predictive coding is under 0.9 of that estimate; of a
// field of 128 KiB to 256 KiB with elements of several bytes, only the one smaller when both
// are coded quickly (the scan encoder's choice, format 1.1); false: every transform coded in
// full (the bytes of format 1.0). estimate_split: transforms 2 and 3 estimated so in a window
// with gaps too, and 4 and 5 the same way on the valid points' values (a trial's size, not a
// stream's bytes: the encoder's choice between its coders, EncoderTuning::attr_estimate).
std::vector<uint8_t> encode_attributes(const std::vector<AttrSpec>& specs,
                                       const std::vector<std::vector<uint8_t>>& data,
                                       const uint8_t* valid, size_t frames, size_t points,
                                       size_t width, const int32_t* q = nullptr,
                                       bool estimate = false, const RaggedFields* ragged = nullptr,
                                       bool estimate_split = false);

// encode_attributes, with the float fields given a bound (bounds[a] > 0 for specs[a]; --attr-error,
// FORMAT.md 5.5 and 16.4) coded within it: *data holds the values as read; each bounded field is
// coded as it is and with its finite values quantised (quantise_field), and the quantised values
// replace *data's only when their coding is smaller (exact is within any bound, so a bound never
// makes a field's coding larger). On return *data holds the values the decoder gives back.
// bounds: one per spec or empty (then encode_attributes' bytes).
std::vector<uint8_t> encode_attributes_within(
    const std::vector<AttrSpec>& specs, const std::vector<double>& bounds,
    std::vector<std::vector<uint8_t>>* data, const uint8_t* valid, size_t frames, size_t points,
    size_t width, const int32_t* q = nullptr, bool estimate = false,
    const RaggedFields* ragged = nullptr, bool estimate_split = false);

// FORMAT.md 16.4, "a field within a bound": each finite value v of a float field (elements of
// s.size bytes, little-endian) replaced by q = float(round(v / (2 bound)) 2 bound) in the field's
// own float type when |q - v| <= bound. True when some value changed.
bool quantise_field(const AttrSpec& s, double bound, std::vector<uint8_t>* bytes);

// The bounds of a PCD layout's attributes, one per attribute_specs(layout.fields) entry (0: exact),
// from layout.field_bounds (one per field, x y z included); empty when it is.
std::vector<double> attribute_bounds(const PCDExtra& layout);

// Decodes what encode_attributes wrote into *out (one byte array per spec, resized). Throws
// Error(kCorrupt) naming `what` on a bad transform or predictor, a window larger than the
// payload can hold (checked before allocating), a truncated block or bytes left over.
// q: the window's POSW integers (frames x points x 3), nullptr when it has none (then
// predictors 10 and 11 are corrupt). ragged: as encode_attributes was given (predictor 12 is
// corrupt without it).
void decode_attributes(const uint8_t* data, size_t size, const std::vector<AttrSpec>& specs,
                       const uint8_t* valid, size_t frames, size_t points, size_t width,
                       std::vector<std::vector<uint8_t>>* out, const std::string& what,
                       const int32_t* q = nullptr, const RaggedFields* ragged = nullptr);

}  // namespace capz
