// capz — C3D internals shared by the reader and the writer: the file's header and data
// layout, frames and rotations by parts. The parameter section and the number forms are in
// coding/c3d_params.h (the .capz container stores the section as it is).
//
// C3D layout (512-byte blocks, block numbers count from 1):
//   block 1            header: byte 0 = first parameter block, byte 1 = 0x50, then 16-bit words
//   block P..P+n-1     parameter section: 4-byte section header (byte 2 = n blocks, byte 3 =
//                      83 + processor type), then groups and parameters
//   block D..          data: per frame, points x {x, y, z, word4}, then analog samples x channels
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "capz/io.h"
#include "capz/take.h"
#include "coding/c3d_params.h"

namespace capz {
namespace c3d {

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
