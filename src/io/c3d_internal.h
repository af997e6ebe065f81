// capz — C3D internals shared by the reader, the writer and the parameter codec.
//
// C3D layout (512-byte blocks, block numbers count from 1):
//   block 1            header: byte 0 = first parameter block, byte 1 = 0x50, then 16-bit words
//   block P..P+n-1     parameter section: 4-byte section header (byte 2 = n blocks, byte 3 =
//                      83 + processor type), then groups and parameters
//   block D..          data: per frame, points x {x, y, z, word4}, then analog samples x channels
// Numbers are in the processor's form everywhere (header, parameters, data):
//   84 Intel: little-endian int16, little-endian IEEE float32
//   85 DEC:   little-endian int16, VAX F-float (16-bit words high-word first, exponent bias 128)
//   86 MIPS:  big-endian int16, big-endian IEEE float32
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "capz/io.h"
#include "capz/take.h"

namespace capz {
namespace c3d {

constexpr size_t kBlock = 512;
constexpr int kIntel = 84;
constexpr int kDec = 85;
constexpr int kMips = 86;

// VAX F-float in file byte order (4 bytes) -> IEEE float. Exponent 0 gives 0 (the VAX reserved
// operand, sign set and exponent 0, also gives 0). Exact for every VAX value whose IEEE
// counterpart is a normal number; the two smallest VAX exponents become IEEE denormals.
float dec_to_float(const uint8_t* p);
// IEEE float -> VAX F-float bytes (used to build DEC test files). NaN and infinities, which VAX
// cannot represent, become the largest finite VAX value of the same sign; tiny values become 0.
void float_to_dec(float v, uint8_t* out);

// Whether the host stores numbers little-endian: then a little-endian number in a file is one
// memcpy (the frame readers and writers move every coordinate through these), else byte by byte.
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
constexpr bool kHostLittleEndian = true;
#else
constexpr bool kHostLittleEndian = false;
#endif

// The 32-bit word of 4 bytes in little-endian order.
inline uint32_t get_u32le(const uint8_t* p) {
  uint32_t u;
  if (kHostLittleEndian) {
    std::memcpy(&u, p, 4);
    return u;
  }
  return static_cast<uint32_t>(p[0]) | (static_cast<uint32_t>(p[1]) << 8) |
         (static_cast<uint32_t>(p[2]) << 16) | (static_cast<uint32_t>(p[3]) << 24);
}

// Reads numbers stored in one processor's form.
struct NumberFormat {
  int processor = kIntel;
  uint16_t u16(const uint8_t* p) const {
    return processor == kMips ? static_cast<uint16_t>((p[0] << 8) | p[1])
                              : static_cast<uint16_t>(p[0] | (p[1] << 8));
  }
  int16_t i16(const uint8_t* p) const { return static_cast<int16_t>(u16(p)); }
  float f32(const uint8_t* p) const {
    if (processor == kDec) return dec_to_float(p);
    uint32_t u;
    if (processor == kMips)
      u = (static_cast<uint32_t>(p[0]) << 24) | (static_cast<uint32_t>(p[1]) << 16) |
          (static_cast<uint32_t>(p[2]) << 8) | p[3];
    else
      u = get_u32le(p);
    float f;
    std::memcpy(&f, &u, 4);
    return f;
  }
};

// Host form used inside C3DParameter::data and written by capz: little-endian. Inline: the
// frame readers and writers call them per coordinate.
inline void put_u16le(uint16_t v, uint8_t* out) {
  out[0] = static_cast<uint8_t>(v & 0xff);
  out[1] = static_cast<uint8_t>(v >> 8);
}
inline void put_f32le(float v, uint8_t* out) {
  if (kHostLittleEndian) {  // the float's bytes as they are (a NaN keeps its bits either way)
    std::memcpy(out, &v, 4);
    return;
  }
  uint32_t u;
  std::memcpy(&u, &v, 4);
  for (int i = 0; i < 4; ++i) out[i] = static_cast<uint8_t>(u >> (8 * i));
}
inline float get_f32le(const uint8_t* p) {
  const uint32_t u = get_u32le(p);
  float f;
  std::memcpy(&f, &u, 4);
  return f;
}

// A parsed parameter section.
struct ParameterSection {
  int processor = kIntel;
  int declared_blocks = 0;  // byte 2 of the section header
  std::vector<C3DGroup> groups;
  std::vector<std::string> warnings;  // faults that lost something ("entry at byte 1234: ...")
  std::vector<std::string> notes;     // oddities kept as they are (two groups sharing an id)
};

// Parses the parameter section starting at data[offset] (its 4-byte header); entries must start
// before `limit` (the data section when it follows the parameters, else the file size: the
// block count in the section header is often understated). Values are converted to host form.
// Tolerant: an entry that cannot be decoded ends the parse with a warning; what was read before it
// is kept. Throws Error(kCorrupt) only if the 4-byte header itself is missing, and
// Error(kUnsupportedVersion) for a processor byte other than 84..86.
ParameterSection parse_parameter_section(const uint8_t* data, size_t size, size_t offset,
                                         size_t limit, const std::string& name);

// The section in Intel form, padded with zeros to whole 512-byte blocks; byte 2 = block count.
// Groups are written in order, each followed by its parameters. Throws Error(kUsage) if a name
// is empty or longer than 127 bytes, a description longer than 255 bytes, a dimension outside
// 0..255, more than 7 dimensions, data not matching the dimensions, or more than 255 blocks.
std::vector<uint8_t> encode_parameter_section(const std::vector<C3DGroup>& groups);

// ---- parameter helpers (host form) --------------------------------------------------------

// Strings from a char parameter and its numbered continuations: base, base2, base3, ...
// (e.g. LABELS, LABELS2). Empty when the base parameter is absent or not a char array.
std::vector<std::string> string_list(const C3DExtra& extra, const std::string& group,
                                     const std::string& base);
// The same for a numeric parameter (e.g. ANALOG:SCALE, SCALE2: a parameter holds at most 255
// entries, so files with more analog channels continue it), as floats; it stops at the first
// continuation absent or not numeric. Empty when the base parameter is absent or a char array.
std::vector<float> float_list(const C3DExtra& extra, const std::string& group,
                              const std::string& base);
// POINT:UNITS as one unit name: the first of its entries (a 2-D char array's strings, or a 1-D
// one's blank-separated words; trimmed; empty ones skipped) when every entry names the same unit
// (the same units_to_metres factor, or the same letters ignoring case for names capz does not
// know). When they disagree: the distinct entries joined by ", " (which no unit parses as, so a
// bound in length units is refused) and *disagreement says which they are. "" when the
// parameter is absent, empty or not a char array.
std::string point_units(const C3DExtra& extra, std::string* disagreement = nullptr);
// First element of a numeric parameter, or `fallback` when absent / empty / not numeric.
double number_param(const C3DExtra& extra, const std::string& group, const std::string& name,
                    double fallback);
bool has_param(const C3DExtra& extra, const std::string& group, const std::string& name);

C3DGroup& ensure_group(std::vector<C3DGroup>& groups, const std::string& name,
                       const std::string& description);
C3DParameter& ensure_param(C3DGroup& group, const std::string& name,
                           const std::string& description);
C3DGroup* find_group(std::vector<C3DGroup>& groups, const std::string& name);
C3DParameter* find_param(C3DGroup& group, const std::string& name);

// Setters replace type, dims and data only when the value differs from what is stored, so a
// parameter that already holds the value keeps its exact bytes and shape.
// value in -32768..65535 (stored as its 16 bits); a one-byte parameter stays one byte for 0..255.
void set_int16(C3DParameter& p, int value);
// A byte array stays bytes while every value is 0..255.
void set_int16_array(C3DParameter& p, const std::vector<int>& values);
void set_float(C3DParameter& p, float value);
void set_string(C3DParameter& p, const std::string& s);
// 2-D char array: dims {max(len, min_len), count}, each string blank padded.
void set_strings(C3DParameter& p, const std::vector<std::string>& v, size_t min_len = 1);

// Writes `values` as base, base2, base3 ... (at most `per_param` each), removing continuation
// parameters no longer needed. Keeps the base parameter's string length when it is long enough.
void set_string_list(C3DGroup& group, const std::string& base, const std::vector<std::string>& v,
                     const std::string& description, size_t per_param = 255);

// ---- reading by parts (c3d_read.cpp): header and parameters first, frames on demand ----------

// Where and how the frames are stored, as read_header found it.
struct DataLayout {
  NumberFormat nf;
  size_t data_offset = 0;  // file offset of frame 0
  size_t per_frame = 0;    // bytes per frame
  size_t frames = 0, points = 0;
  size_t analog_values = 0;  // analog samples per frame x channels
  bool float_storage = false;
  bool analog_unsigned = false;  // ANALOG:FORMAT = UNSIGNED (int16 files)
  double scale = 1;              // |POINT:SCALE| as used for int16 coordinates
  size_t warning_at = 0;         // where in Take::warnings a warning about the frames belongs
  // The ROTATION section (rot_per_frame = 0 when the take has none): from file offset
  // rot_offset, per point frame rot_samples_per_frame x rot_segments rotations of
  // kRotationBytes each.
  size_t rot_offset = 0, rot_per_frame = 0;
  size_t rot_samples_per_frame = 0, rot_segments = 0;
};

// One stored rotation: 16 float32 matrix elements, column-major, then the reliability float32,
// in the file's number form (ezc3d and Visual3D lay it out so; Rotations in take.h).
constexpr size_t kRotationBytes = 17 * 4;

// Bytes past the parameter section's limit that read_header is also given, for an entry that
// starts before the data section and runs on into it (an entry's next-entry offset is an int16,
// so one entry spans less than 32 KiB).
constexpr size_t kHeaderSlack = size_t{1} << 16;

// How many of the file's first bytes read_header needs, from the first `avail` bytes (at least
// the 512-byte header block when the file has it) of a file of `size` bytes.
size_t header_extent(const uint8_t* data, size_t avail, size_t size);

// Parses the header block and the parameter section from the file's first `avail` bytes
// (avail >= header_extent(), or the whole file) of a file of `size` bytes. Returns the take
// without per-frame arrays (frames, points, labels, rate, units, analog layout, C3D extra with
// empty residual / camera_mask) and the data layout. Every check and warning of read_c3d except
// the ones about frame contents.
Take read_header(const uint8_t* data, size_t avail, size_t size, const std::string& name,
                 DataLayout* lay);

// Decodes `count` frames stored at `bytes` (count * lay.per_frame bytes) into the per-frame
// arrays (take.h layouts, all for `count` frames). Counts 4th words beyond 16 bits in *wide_word4.
void decode_frames(const DataLayout& lay, const uint8_t* bytes, size_t count, double* xyz,
                   uint8_t* valid, float* residual, uint8_t* camera, double* analog,
                   size_t* wide_word4);
std::string wide_word4_warning(size_t count);
// Decodes `count` stored rotations (samples x segments, count * kRotationBytes bytes at `bytes`)
// into matrices (count x 16) and reliability (count), take.h's layouts.
void decode_c3d_rotations(const DataLayout& lay, const uint8_t* bytes, size_t count,
                          float* matrices, float* reliability);

// ---- writing by parts (c3d_write.cpp): header and parameters first, then frames -------------

// What the writer must know of the frames before its header: the largest |coordinate| (for a
// take without a usable POINT:SCALE) and whether every valid coordinate fits int16 at `scale`
// and every analog value is an integer in -32768..65535.
struct C3DWriteScan {
  double scale = 0;  // the int16 step checked (0: fit not checked)
  double max_abs = 0;
  bool fits = true;
  // count samples (xyz: count x 3, valid: count) and analog_count analog values.
  void add(size_t count, const double* xyz, const uint8_t* valid, size_t analog_count,
           const double* analog);
};
// float32(|POINT:SCALE|) when usable, else 0 (then c3d_scale_from_data applies).
double c3d_known_scale(const Take& take);
double c3d_scale_from_data(double max_abs);
// True when the header depends on the frames (int16 storage, or no usable scale).
bool c3d_needs_scan(const Take& take, const WriteOptions& opts);
// Throws kUsage when the take does not fit C3D's counts.
void check_c3d_limits(const Take& take, const std::string& name);
// Throws kInternal when take.rotations' arrays do not have the shapes take.h gives.
void check_c3d_rotations(const Take& take, const std::string& name);

struct C3DFilePlan {
  bool float_storage = false;
  double scale = 1;
  bool have_res = false;  // frames carry residual / camera words
  size_t frames = 0, points = 0, analog_total = 0;
  size_t per_frame = 0;       // bytes per frame
  std::vector<uint8_t> head;  // header block + parameter section: the bytes before frame 0
  // Rotations (rot_bytes = 0 without): file offset (a block boundary at or past the frames'
  // end; zeros between) and size of the rotation section.
  size_t rot_offset = 0, rot_bytes = 0;
};
// `take`: metadata and frame count (per-frame arrays not used).
C3DFilePlan plan_c3d_file(const Take& take, bool have_res, const WriteOptions& opts,
                          const C3DWriteScan& scan, const std::string& name);
// `count` frames into out (count * plan.per_frame bytes). residual/camera unused (may be null)
// when !plan.have_res. points_fit (int16 storage; may be null): set to whether every valid
// coordinate fits int16 at plan.scale (C3DWriteScan's check, made while rounding); where one
// does not, the bytes written wrap and are not a faithful file.
void encode_c3d_frames(const C3DFilePlan& plan, size_t count, const double* xyz,
                       const uint8_t* valid, const float* residual, const uint8_t* camera,
                       const double* analog, uint8_t* out, bool* points_fit = nullptr);

// `count` rotations (samples x segments; matrices count x 16, reliability count) into out
// (count x kRotationBytes bytes, Intel form), laid out as decode_c3d_rotations reads them.
void encode_c3d_rotations(const float* matrices, const float* reliability, size_t count,
                          uint8_t* out);

// The whole file write_c3d writes, in memory (`name` only for messages).
std::vector<uint8_t> encode_c3d_file(const Take& take, const WriteOptions& opts,
                                     const std::string& name);

}  // namespace c3d
}  // namespace capz
