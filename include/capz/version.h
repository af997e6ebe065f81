// capz — versions: of the library, and of the .capz format it writes and reads (docs/FORMAT.md 17).
// The CAPZ_VERSION_* numbers are the one place the library version is kept: CMakeLists.txt
// reads them for project(VERSION).
#pragma once

#define CAPZ_VERSION_MAJOR 0
#define CAPZ_VERSION_MINOR 1
#define CAPZ_VERSION_PATCH 0

namespace capz {

struct Version {
  int major = 0, minor = 0, patch = 0;
};
struct FormatVersion {
  int major = 0, minor = 0;
};
// True when a is b or a later version.
constexpr bool operator>=(FormatVersion a, FormatVersion b) {
  return a.major != b.major ? a.major > b.major : a.minor >= b.minor;
}

// The version of the headers in use.
constexpr Version kVersion{CAPZ_VERSION_MAJOR, CAPZ_VERSION_MINOR, CAPZ_VERSION_PATCH};
// The version of the library linked (differs from kVersion only when headers and library
// come from different builds).
Version library_version();
// "0.1.0"
const char* version_string();

// The .capz version streams are written in, but for those of kFormat6 to kFormat9.
constexpr FormatVersion kFormatWritten{5, 0};
// The version of streams with point fields that include a normal triple or are organized
// (FORMAT.md 13: ATTR predictor 9, transforms 4 and 5).
constexpr FormatVersion kFormat6{6, 0};
// The version of streams whose scan found what format 7 codes (FORMAT.md 7): PCD points moving
// along their rays (POSW predictor 10, 7.1), repeated analog frames (7.2), or the point fields
// of an unorganized cloud whose positions are on the grid (ATTR predictors 10 and 11, 7.3).
// Every other stream is kFormatWritten or kFormat6.
constexpr FormatVersion kFormat7{7, 0};
// The version of streams whose META is coded after a preset dictionary (FORMAT.md 5.1: C3D
// takes, when that is the smallest coding), but for those with analog channels (kFormat9).
// Every 7.x addition holds in 8.x.
constexpr FormatVersion kFormat8{8, 0};
// The version of streams with analog channels (FORMAT.md 11.9: the float coder's predictors 2-5;
// 9.2: interpolated samples; 9.3, from 9.1 on: constant predictors of integer channels' blocks;
// 9.4, from 9.2 on: held samples; 9.7, from 9.3 on: tokens relative to the magnitude context).
// Every 8.x addition holds in 9.x.
constexpr FormatVersion kFormat9{9, 3};
// The newest version the encoder writes.
constexpr FormatVersion kFormatNewestWritten = kFormat9;
// The versions read: every one from kFormatOldestRead to kFormatNewestRead, and any later
// minor version of kFormatNewestRead's major (minor versions only add what older decoders skip;
// FORMAT.md 17). A later major version is refused (Error kUnsupportedVersion).
constexpr FormatVersion kFormatOldestRead{1, 0};
constexpr FormatVersion kFormatNewestRead{9, 3};

}  // namespace capz
