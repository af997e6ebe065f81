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

// Reads numbers stored in one processor's form.
struct NumberFormat {
  int processor = kIntel;
  uint16_t u16(const uint8_t* p) const {
    return processor == kMips ? static_cast<uint16_t>((p[0] << 8) | p[1])
                              : static_cast<uint16_t>(p[0] | (p[1] << 8));
  }
  int16_t i16(const uint8_t* p) const { return static_cast<int16_t>(u16(p)); }
  float f32(const uint8_t* p) const;
};

// Host form used inside C3DParameter::data and written by capz: little-endian.
void put_u16le(uint16_t v, uint8_t* out);
void put_f32le(float v, uint8_t* out);
float get_f32le(const uint8_t* p);

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
void set_int16(C3DParameter& p, int value);  // value in -32768..65535 (stored as its 16 bits)
void set_int16_array(C3DParameter& p, const std::vector<int>& values);
void set_float(C3DParameter& p, float value);
void set_string(C3DParameter& p, const std::string& s);
// 2-D char array: dims {max(len, min_len), count}, each string blank padded.
void set_strings(C3DParameter& p, const std::vector<std::string>& v, size_t min_len = 1);

// Writes `values` as base, base2, base3 ... (at most `per_param` each), removing continuation
// parameters no longer needed. Keeps the base parameter's string length when it is long enough.
void set_string_list(C3DGroup& group, const std::string& base, const std::vector<std::string>& v,
                     const std::string& description, size_t per_param = 255);

// The whole file write_c3d writes, in memory (`name` only for messages).
std::vector<uint8_t> encode_c3d_file(const Take& take, const WriteOptions& opts,
                                     const std::string& name);

}  // namespace c3d
}  // namespace capz
