// capz — the Take: the one data model every reader fills, every writer reads and every codec sees.
//
// Shapes (frame-major, row-major), for a fixed take (every frame has `points` points):
//   xyz   : frames x points x 3 doubles, xyz[(f * points + p) * 3 + axis], in the file's own units
//   valid : frames x points bytes, 1 = the sample holds a measured position, 0 = a gap
// A ragged take (frames of their own point count: LiDAR sweeps, clouds without their NaN pixels)
// has frame_offsets: frames + 1 non-decreasing offsets, frame_offsets[0] == 0; frame f holds
// points [frame_offsets[f], frame_offsets[f + 1]) of the flattened arrays, so xyz is total x 3,
// valid is total, every PointAttribute::data total x count x size, in one point order; `points`
// is 0 and `labels` empty. frame_begin / frame_points / total_points / at serve both cases.
// A gap sample's xyz is unspecified by contract (readers store 0); codecs fill gaps for coding
// only and must never rely on the value. Every source format is converted exactly into double:
// float32 values are widened, C3D int16 values are stored as int16 * POINT:SCALE (so the stored
// integer is recovered as round(x / scale)).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace capz {

// A folder format (kPCDFolder, kPLYFolder, kBinFolder) also stands for a single frame file of
// that format read as a one-frame take (its extras name the one file).
enum class Format {
  kUnknown = 0,
  kC3D = 1,
  kTRC = 2,
  kPCDFolder = 3,
  kBinFolder = 4,  // KITTI-style .bin frames: float32 x y z intensity, no header
  kPLYFolder = 5,  // PLY frames: element vertex with x y z and any scalar properties
};
// "c3d", "trc", "pcd-folder", "bin-folder", "ply-folder", "unknown"
const char* format_name(Format f);
// PCD, PLY and .bin frames: point clouds, whose points have no labels (Take::labels empty).
bool is_frame_files(Format f);

// ---------------------------------------------------------------------------------------------
// C3D specifics: what a C3D carries beyond positions, kept so a C3D written back is faithful.

// One parameter of the C3D parameter section, values decoded to host form.
struct C3DParameter {
  std::string name;         // as stored (upper case in practice)
  std::string description;  //
  bool locked = false;      // stored as a negative name length
  int8_t type = -1;         // -1 char, 1 byte, 2 int16, 4 float (element size = |type|)
  std::vector<int> dims;    // 0..7 dimensions, first varies fastest; empty = scalar
  // Elements in host order: char/byte as bytes, int16 as little-endian int16, float as
  // little-endian IEEE float32 (DEC floats are converted on read). Size = |type| * prod(dims).
  std::vector<uint8_t> data;

  size_t element_count() const;
  const char* type_name() const;  // "char", "byte", "int16" or "float"
  // Typed views; they throw Error(kCorrupt) on a type mismatch.
  std::string as_string() const;                // the whole char array, trailing blanks removed
  std::vector<std::string> as_strings() const;  // 2-D char array: dims[1] strings of dims[0]
  std::vector<int> as_ints() const;             // byte (unsigned) or int16 elements
  std::vector<float> as_floats() const;         // float, int16 or byte elements widened
};

struct C3DGroup {
  int id = 0;  // positive group number (parameters refer to it)
  std::string name;
  std::string description;
  bool locked = false;
  // Parameters naming a group id that has no group entry in the file: kept under an unnamed
  // group with implicit = true, written back as they were (parameters only, no group entry).
  bool implicit = false;
  std::vector<C3DParameter> params;

  const C3DParameter* find(const std::string& name) const;  // case-insensitive, nullptr if absent
  // Its name, or "#<id>" for a group without one (an implicit group): how the CLI and Python
  // name it.
  std::string key() const;
};

struct C3DHeaderEvent {
  float time = 0;  // seconds
  bool display = false;
  std::string label;  // up to 4 characters
};

struct C3DExtra {
  int processor = 84;          // as read: 84 Intel, 85 DEC, 86 MIPS (the writer writes Intel)
  bool float_storage = false;  // POINT:SCALE < 0
  double point_scale = 1.0;    // |POINT:SCALE|: the int16 step in the file's units
  int max_interpolation_gap = 0;
  std::vector<C3DGroup> groups;  // the whole parameter section in file order
  std::vector<C3DHeaderEvent> header_events;
  bool header_events_label_range = false;  // header word 150 (0x3039 = events with 4-char labels)

  // Per sample 4th word, both frames x points (empty when the take did not come from C3D):
  // residual = low byte x point_scale in file units for a valid sample, -1 for a gap; camera_mask
  // = the high byte (0 for a gap). The writer stores round(residual / scale) and mask & 0x7f.
  // See docs/C3D.md for what the reader counts as a gap.
  std::vector<float> residual;
  std::vector<uint8_t> camera_mask;

  const C3DGroup* group(const std::string& name) const;  // case-insensitive, nullptr if absent
  const C3DParameter* param(const std::string& group, const std::string& name) const;
};

// Analog channels sampled `samples_per_frame` times per point frame.
// values: (frames * samples_per_frame) x channels, row-major, exactly as stored in the file
// (int16 files give integers, float files give the float32 values). Real units follow from
// ANALOG:SCALE/OFFSET/GEN_SCALE in the C3D parameters; capz keeps the stored numbers.
struct Analog {
  int channels = 0;
  int samples_per_frame = 0;
  double rate = 0;  // Hz
  std::vector<std::string> labels;
  std::vector<double> values;
  // Lossy channels (docs/FORMAT.md 5.7), per channel, empty when every channel is lossless:
  // bounds[c] > 0 is the bound of channel c in its physical units (0: lossless), factors[c] the
  // physical units per stored unit, |ANALOG:SCALE x GEN_SCALE| (1 for other sources). Set by
  // the encoder from CompressOptions::analog_max_error, read back from archives.
  std::vector<double> bounds, factors;
  bool lossy() const {
    for (double b : bounds)
      if (b > 0) return true;
    return false;
  }
};

// One event of the C3D EVENT group, where C3D writers keep a take's events (foot strikes, foot
// offs, ...): its label, context ("Left", "Right", "General"), description and subject, its time
// in seconds (EVENT:TIMES' minutes x 60 + seconds), icon id and generic flag.
struct C3DEvent {
  std::string label, context, description, subject;
  double time = 0;
  int icon_id = 0, generic_flag = 0;
};
// The EVENT group's events in stored order: EVENT:USED of them (read unsigned; as many as TIMES
// holds when USED is absent), never more than TIMES holds (minute, second) pairs for; a text or
// number whose parameter is absent or shorter is "" or 0. Empty without an EVENT group. The
// header's 18-slot event table is C3DExtra::header_events.
std::vector<C3DEvent> c3d_events(const C3DExtra& c3d);
// Replaces the EVENT group's events (the group added when absent): USED, TIMES (minutes and the
// seconds left, so long takes keep float32's precision), LABELS, CONTEXTS, DESCRIPTIONS,
// SUBJECTS, ICON_IDS and GENERIC_FLAGS; the group's other parameters are kept. Throws
// kInvalidParameter, changing nothing, for more than 255 events (a C3D dimension's limit), a
// time that is negative or not finite, or an icon id or flag outside int16.
void set_c3d_events(C3DExtra* c3d, const std::vector<C3DEvent>& events);

// Per analog channel, what gives the stored values physical units (docs/FORMAT.md 5.7): the
// factor |ANALOG:SCALE x GEN_SCALE| (1 when the take has no C3D parameters or they are
// unreadable), the stored value of physical zero (ANALOG:OFFSET, 0 without), the unit
// (ANALOG:UNITS, trimmed, "" without) and the storage (C3D int16, or uint16 with ANALOG:FORMAT
// UNSIGNED; else floats). Physical value = (stored - offset) * factor, up to SCALE's sign.
struct AnalogPhysics {
  double factor = 1, offset = 0;
  double scale = 1;  // ANALOG:SCALE x GEN_SCALE with its sign: physical = (stored - offset) x scale
  std::string unit;
  bool integers = false;  // int16 / uint16 storage
  double lo = 0, hi = 0;  // the storage's range
};
struct Take;
std::vector<AnalogPhysics> analog_physics(const Take& t);
// One spelling for the analog units C3D writers spell several ways, so that a bound given for
// "V" also bounds "Volt" and "Volts" channels: V, mV, uV, N, Nm, Nmm (case-insensitive:
// "volt", "nt", "ntmm", "N-M", "N.mm", "newtons", ...); any other unit trimmed, as written.
std::string canonical_analog_unit(const std::string& unit);

// Rotation signals (the C3D ROTATION group that Visual3D, Theia and ezc3d use): per segment a
// 4x4 transform from the segment's local coordinates to the lab's, and a reliability value,
// sampled `samples_per_frame` times per point frame. Shapes (sample-major, as the C3D stores
// them), with samples = frames * samples_per_frame:
//   matrices    : samples x segments x 16 float32, matrices[(s * segments + g) * 16 + k], k the
//                 element's index in column-major order (row = k % 4, column = k / 4)
//   reliability : samples x segments float32, reliability[s * segments + g]
// Values are the float32s the file holds, bit for bit (NaN payloads kept; DEC floats
// converted). segments == 0: no rotations (both arrays empty).
struct Rotations {
  int segments = 0;                 // ROTATION:USED
  int samples_per_frame = 0;        // ROTATION:RATIO (>= 1 when segments > 0)
  double rate = 0;                  // Hz, ROTATION:RATE (0 when the file gives none)
  std::vector<std::string> labels;  // one per segment (may be empty strings)
  std::vector<float> matrices;
  std::vector<float> reliability;

  size_t samples(size_t frames) const {
    return segments > 0 ? frames * static_cast<size_t>(samples_per_frame) : 0;
  }
  // Rotations (samples x segments) per point frame: 0 without.
  size_t per_frame() const {
    return segments > 0 ? static_cast<size_t>(samples_per_frame) * static_cast<size_t>(segments)
                        : 0;
  }
};

// TRC specifics (OpenSim / Motion Analysis). Kept so a TRC written back looks like the source.
struct TRCExtra {
  std::string
      path_file_type_line;  // first line verbatim, e.g. "PathFileType\t4\t(X/Y/Z)\tname.trc"
  double camera_rate = 0;
  double orig_data_rate = 0;
  int64_t orig_data_start_frame = 1;
  int64_t orig_num_frames = 0;
  std::vector<double> times;           // the Time column, one per frame
  std::vector<int64_t> frame_numbers;  // the Frame# column, one per frame
  int decimals = -1;                   // most decimals seen in coordinate fields; -1 unknown
  int time_decimals = -1;              // most decimals seen in the Time column; -1 unknown
};

// One per-point attribute channel: a field of the source other than x y z (a PCD field:
// colour, intensity, normals, labels, ring, time, descriptors), one value (or `count` values)
// per point and frame. data holds frames x points x count elements of `size` bytes each,
// data[((f * points + p) * count + k) * size + b], little-endian, exactly the bytes the file
// holds (float NaN payloads and PCL's packed "rgb" float kept bit for bit).
struct PointAttribute {
  std::string name;  // as the source spells it ("rgb", "normal_x", "_" for padding)
  char type = 'F';   // 'F' float, 'U' unsigned integer, 'I' signed integer
  int size = 4;      // bytes per element: 1, 2, 4 or 8 (F: 4 or 8)
  int count = 1;     // elements per point (PCD COUNT), >= 1
  std::vector<uint8_t> data;

  size_t bytes_per_point() const { return static_cast<size_t>(size) * static_cast<size_t>(count); }
};

// One field of a PCD frame's layout, x y z included.
struct PCDField {
  std::string name;
  char type = 'F';
  int size = 4;
  int count = 1;
};

// The point attribute a PCD field other than x, y and z becomes (its samples not yet read).
inline PointAttribute attribute_of(const PCDField& f) {
  PointAttribute a;
  a.name = f.name;
  a.type = f.type;
  a.size = f.size;
  a.count = f.count;
  return a;
}

// A field form the format and the PCD writer hold (docs/FORMAT.md 5.5): TYPE F, U or I; SIZE 1,
// 2, 4 or 8 (4 or 8 for F); COUNT 1 .. 2^20. The one rule for META's decoder and the encoder.
inline bool valid_field_form(char type, int size, uint64_t count) {
  return (type == 'F' || type == 'U' || type == 'I') &&
         (size == 1 || size == 2 || size == 4 || size == 8) && (type != 'F' || size >= 4) &&
         count >= 1 && count <= (uint64_t{1} << 20);
}

// PCD folder specifics.
struct PCDExtra {
  std::vector<std::string> frame_names;  // file names in natural-sort order, one per frame
  std::string encoding = "binary";       // "ascii", "binary" or "binary_compressed" (first file)
  std::string version = "0.7";           // the VERSION line's value
  // Every field in the file's order, x y z included; empty means "x y z", F, 4 bytes each.
  std::vector<PCDField> fields;
  size_t width = 0;               // WIDTH; 0: points (unorganized)
  size_t height = 1;              // HEIGHT; > 1: an organized cloud, width x height = points
  std::vector<double> viewpoint;  // VIEWPOINT's 7 values (tx ty tz qw qx qy qz); empty: default
  // Per entry of `fields`, the bound its values were coded within (0: lossless); empty: all
  // lossless. Set by the encoder from CompressOptions::attr_error, read back from archives.
  std::vector<double> field_bounds;
};

// .bin folder specifics. A .bin frame has no header: a record a point, float32 x y z then the
// fields bin_record_of gives (below), which the take holds as point attributes.
struct BinExtra {
  std::vector<std::string> frame_names;  // file names in natural-sort order, one per frame
  // A record a user declared (--bin-fields, parse_bin_record) that is not the frame names'
  // (bin_record_fields): `record` its fields after x y z (none: x y z alone). Not declared: the
  // names' record, `record` empty.
  bool declared = false;
  std::vector<PCDField> record;
};

// Whether a .bin frame file's name is a nuScenes sweep's, NAME.pcd.bin (as nuScenes and Lyft
// name them).
bool nuscenes_bin_name(const std::string& name);
// The fields of a .bin frame's record after x y z by the frame files' names (docs/FORMAT.md
// "Frame-file sources"), each float32: nuScenes' "intensity" "ring" when every name is
// nuscenes_bin_name, else KITTI's "intensity" (no names too). Empty when some are and some are
// not: no one record holds such frames.
std::vector<PCDField> bin_record_fields(const std::vector<std::string>& frame_names);
// bin_record_fields, but KITTI's record for names of both kinds (a writer's fallback).
std::vector<PCDField> bin_record_or_kitti(const std::vector<std::string>& frame_names);
// "x y z intensity ring:U2": the record's values in order (the fields after x y z given), a field
// other than a float32 with its TYPE and SIZE.
std::string bin_record_text(const std::vector<PCDField>& record);
// Whether two records have the same fields (names, types and sizes) in the same order.
bool same_bin_records(const std::vector<PCDField>& a, const std::vector<PCDField>& b);
// Whether every field of a record is a float32 (KITTI's and nuScenes' are).
bool bin_record_float32(const std::vector<PCDField>& record);
// The record a --bin-fields text declares, its fields after x y z: names separated by spaces or
// commas, each with an optional ":TYPE" (F4 F8 U1 U2 U4 U8 I1 I2 I4 I8, either case; F4 when
// none), "x y z" first (float32), "_" a padding field. Throws Error(kUsage) naming `what` for
// another text (x y z missing or typed otherwise, a name twice, an unknown type).
std::vector<PCDField> parse_bin_record(const std::string& text, const std::string& what);

// PLY folder specifics: the vertex element's layout and the header's text, so a PLY written
// back looks like the source.
struct PLYExtra {
  std::vector<std::string> frame_names;           // file names in natural-sort order
  std::string encoding = "binary_little_endian";  // or "ascii", "binary_big_endian" (first file)
  std::string version = "1.0";                    // the format line's version
  // Every vertex property in the file's order, x y z included (x y z: F 4 or F 8); COUNT 1.
  std::vector<PCDField> fields;
  // Per entry of `fields`, the type as the file spells it ("float", "float32", "uchar"); empty:
  // the canonical names (char uchar short ushort int uint float double).
  std::vector<std::string> type_names;
  std::vector<std::string> comments;  // the first file's comment lines, without "comment "
  std::vector<std::string> obj_info;  // its obj_info lines, without "obj_info "
};

// ---------------------------------------------------------------------------------------------
struct Take {
  std::string source;  // path it was read from (for messages), may be empty
  Format format = Format::kUnknown;

  size_t frames = 0;
  size_t points = 0;  // per frame in a fixed take; 0 in a ragged take
  // Empty: a fixed take. Else a ragged take: frames + 1 offsets (see top of file).
  std::vector<size_t> frame_offsets;
  std::vector<double> xyz;     // total_points() x 3 (see top of file)
  std::vector<uint8_t> valid;  // total_points()

  double rate = 0;    // frames per second; 0 = unknown
  std::string units;  // "mm", "cm", "m", ... as the file says; empty = unknown
  // True when the file holds no units and the reader assumed `units` (PCD, PLY and .bin frames:
  // metres, as ROS REP 103 and LiDAR drivers write them); --units overrides.
  bool units_assumed = false;
  int64_t first_frame = 1;  // number of the first frame as the source counts them
  // One per point (may be empty strings), or none: a ragged take's, and the points of PCD, PLY
  // and .bin frames (is_frame_files), which carry no labels.
  std::vector<std::string> labels;
  std::vector<std::string> descriptions;  // one per point or empty

  Analog analog;        // channels == 0 when none
  Rotations rotations;  // segments == 0 when none
  // Per-point attribute channels in the source's field order (x y z are xyz); empty when none.
  std::vector<PointAttribute> attributes;
  std::shared_ptr<C3DExtra> c3d;  // set when read from C3D
  std::shared_ptr<TRCExtra> trc;  // set when read from TRC
  std::shared_ptr<PCDExtra> pcd;  // set when read from a PCD folder (or a single .pcd file)
  std::shared_ptr<BinExtra> bin;  // set when read from a .bin folder (or a single .bin file)
  std::shared_ptr<PLYExtra> ply;  // set when read from a PLY folder (or a single .ply file)

  // Inconsistencies found while reading that did not stop it ("header says 1149 frames, file
  // holds 29"). `capz info` prints them.
  std::vector<std::string> warnings;

  bool ragged() const { return !frame_offsets.empty(); }
  // Index of frame f's first point in the flattened arrays (xyz / 3, valid, attribute points).
  size_t frame_begin(size_t f) const { return ragged() ? frame_offsets[f] : f * points; }
  // Points of frame f.
  size_t frame_points(size_t f) const {
    return ragged() ? frame_offsets[f + 1] - frame_offsets[f] : points;
  }
  // Points of all frames: the length of valid (frames x points for a fixed take).
  size_t total_points() const { return ragged() ? frame_offsets.back() : frames * points; }

  double* at(size_t f, size_t p) { return &xyz[(frame_begin(f) + p) * 3]; }
  const double* at(size_t f, size_t p) const { return &xyz[(frame_begin(f) + p) * 3]; }
  bool is_valid(size_t f, size_t p) const { return valid[frame_begin(f) + p] != 0; }
  // The frame files' field list (x y z included): the PCD's or the PLY's header fields; null
  // for other formats (a .bin frame's layout is fixed).
  const std::vector<PCDField>* file_fields() const {
    return pcd ? &pcd->fields : ply ? &ply->fields : nullptr;
  }

  // Allocates xyz and valid for frames x points (all gaps, zero positions): a fixed take
  // (frame_offsets cleared).
  void resize(size_t frames, size_t points);
  // A ragged take of counts.size() frames, frame f holding counts[f] points: frame_offsets set,
  // points 0, labels cleared, xyz and valid allocated (all gaps, zero positions). Attribute
  // arrays are not touched.
  void resize_ragged(const std::vector<size_t>& counts);
  size_t gap_samples() const;  // number of (frame, point) samples that are gaps
  // What is wrong with the shape of the arrays (offsets that are not frames + 1 non-decreasing
  // from 0, xyz / valid / a point attribute not sized for total_points(), points or labels in a
  // ragged take), as a phrase; empty when the shape is right.
  std::string shape_fault() const;
};

// The fields after x y z of the record a .bin frame of `take` is written with: its declared record
// (take.bin->declared: take.bin->record), else those of its .bin frame names (bin_record_fields),
// else KITTI's "intensity".
std::vector<PCDField> bin_record_of(const Take& take);

// What is wrong with the take's point field names, as a phrase (empty when nothing): a field
// named x, y or z (the positions' names in every frame file), two of one name, an empty name, or
// one with a blank or control character (a PCD FIELDS line and a PLY property line split on
// blanks, so such a file would not read back). Checked where a take is made of arrays
// (Python's Take.from_arrays), compressed (take_frames) and written as frame files; a decoded
// archive is not refused for them.
std::string point_field_fault(const Take& take);

// Throws Error(kInvalidParameter) naming `file` (take.source when empty): "ragged takes (frames
// of different point counts) are not supported by <consumer> yet", when take.ragged(); returns
// otherwise.
void refuse_ragged(const Take& take, const std::string& consumer, const std::string& file = "");

// The take's units for people: "mm"; "m (assumed: PCD frames carry no units; --units
// overrides)" when the reader assumed them; "" when unknown.
std::string units_text(const Take& take);

// Per-frame point counts (frames entries) of a fixed or ragged take.
std::vector<size_t> frame_point_counts(const Take& take);
// Offsets (counts.size() + 1, from 0) of frames with these point counts.
std::vector<size_t> offsets_of_counts(const std::vector<size_t>& counts);
// Whether a and b hold the same frames of the same point counts, fixed or ragged: a ragged take
// whose frames all hold a fixed take's count has its shape (the scan coder's frames of one count
// reordered: --point-order any on a folder of fixed-size sweeps decodes to such a ragged take).
bool same_frame_counts(const Take& a, const Take& b);

// The names of the take's point fields (Take::attributes), separated by ", "; empty when none.
std::string field_names(const Take& take);

// Scale factor from one unit's name to metres: "mm" -> 0.001, "cm" -> 0.01, "m" -> 1,
// "in" -> 0.0254; 0 when unknown. Case-insensitive, surrounding blanks ignored. Abbreviations
// (mm cm dm m km um in ft yd) match whole; names spelled out match in either spelling, singular
// or plural ("millimetres", "meter"), or cut short to at least 4 letters ("mete", "mill") when
// the letters name one unit only.
double units_to_metres(const std::string& units);

}  // namespace capz
