// capz — the C3D parameter section: number forms, parsing, encoding, and typed helpers over
// C3DExtra. The .capz container stores C3D parameters in exactly C3D's own layout (META,
// docs/FORMAT.md), so this codec belongs to the coding layer; the C3D reader and writer
// (src/io/c3d_internal.h) build on it. Not part of the public API.
//
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

}  // namespace c3d

// The C3D parameter section alone, in C3D's own byte layout (Intel processor type, blocks of
// 512 bytes, first 4 bytes = the section header). The .capz container stores C3D parameters in
// exactly this form; see docs/FORMAT.md. Throws Error(kUsage) when a parameter cannot be stored
// (a name, description or entry too long for the layout, a bad type or shape).
std::vector<uint8_t> encode_c3d_parameters(const C3DExtra& extra);
// Parses such a section into extra->groups (nothing else of *extra changes); throws
// Error(kCorrupt) naming `name` when the bytes are not a valid section.
void decode_c3d_parameters(const uint8_t* data, size_t size, const std::string& name,
                           C3DExtra* extra);

}  // namespace capz
