// What a stream's format version lets its chunks use (docs/FORMAT.md 2). The file header's
// version is parsed once (check_file_header, container.h) into a StreamFeatures; the decoder
// holds it in its StreamContext and coders read the features from it, never version numbers.
// Format 1.0 has no optional feature: every coding it defines is allowed in every stream. A
// minor version that adds one (scans, 1.1) adds a flag here, set from the stream's minor.
#pragma once

#include <string>

namespace capz {

struct StreamFeatures {
  int minor = 0;  // the stream's minor version of format 1 (messages name it)
  // 1.1: HEAD's feature bit 3, ragged frames coded in SCNW chunks ("Scans (format 1.1)").
  bool ragged_frames() const { return minor >= 1; }
  // 1.1: HEAD's feature bit 4, a frame-file source (PLY or .bin folder) named by HEAD's appended
  // frame_format, and META's PLY block ("Scans (format 1.1)", frame-file sources).
  bool frame_file_sources() const { return minor >= 1; }
  // "1.<minor>", for messages.
  std::string version() const { return "1." + std::to_string(minor); }
};

}  // namespace capz
