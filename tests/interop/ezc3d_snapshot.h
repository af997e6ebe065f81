// What ezc3d (the outside C3D reader, see tests/interop/ezc3d.cmake) reads from a C3D file, as
// plain arrays, so two reads can be compared field by field and the reader object freed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace capz_interop {

// One parameter, values kept in a form where equal values give equal strings: char arrays as
// their strings joined by '\x1f', byte/int16 elements as decimal, floats as their double bits.
struct EzParam {
  std::string group, name, description;
  bool locked = false;
  int type = 0;  // ezc3d::DATA_TYPE: -1 char, 1 byte, 2 int16, 4 float
  std::vector<size_t> dims;
  std::string values;
};

struct EzGroup {
  std::string name, description;
  bool locked = false;
};

// Shapes: xyz frames x points x 3 (NaN where ezc3d reports a gap: residual < 0); residual and
// camera (7 mask bits) frames x points; analog frames x subframes x channels, in the units ezc3d
// gives (stored value minus ANALOG:OFFSET, times ANALOG:SCALE and GEN_SCALE); rotations per
// frame: every subframe's 4x4 matrices (row-major) each followed by its reliability.
struct EzTake {
  size_t frames = 0, points = 0, channels = 0, subframes = 0;
  size_t rotations_per_frame = 0;  // doubles per frame in `rotations`
  std::vector<double> xyz, residual, analog, rotations;
  std::vector<uint8_t> camera;
  // Header words as ezc3d reads them, by name ("first frame", "scale", ...), and its events.
  std::vector<std::pair<std::string, double>> header;
  std::vector<std::string> events;  // "time|display|label"
  std::vector<EzGroup> groups;
  std::vector<EzParam> params;  // group by group, in file order
};

// Reads `path` with ezc3d. Throws whatever ezc3d throws (std::exception) on a file it refuses.
EzTake read_with_ezc3d(const std::string& path);

}  // namespace capz_interop
