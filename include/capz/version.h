// capz — versions: of the library, and of the .capz format it writes and reads (docs/FORMAT.md 17).
// The CAPZ_VERSION_* numbers are the one place the library version is kept: CMakeLists.txt
// reads them for project(VERSION).
#pragma once

#define CAPZ_VERSION_MAJOR 1
#define CAPZ_VERSION_MINOR 0
#define CAPZ_VERSION_PATCH 0

namespace capz {

struct Version {
  int major = 0, minor = 0, patch = 0;
};
struct FormatVersion {
  int major = 0, minor = 0;
};

// The version of the headers in use.
constexpr Version kVersion{CAPZ_VERSION_MAJOR, CAPZ_VERSION_MINOR, CAPZ_VERSION_PATCH};
// The version of the library linked (differs from kVersion only when headers and library
// come from different builds).
Version library_version();
// "1.0.0"
const char* version_string();

// The .capz format (docs/FORMAT.md 2) every stream is written in, but for scans.
constexpr FormatVersion kFormatWritten{1, 0};
// The version of streams of ragged takes (frames of their own point counts: docs/FORMAT.md
// "Scans (format 1.1)"), the first minor version: HEAD's feature bit 3 and the SCNW chunk; also
// of takes read from PLY or .bin frames (HEAD's feature bit 4), whatever their shape.
constexpr FormatVersion kFormatScans{1, 1};
// The newest format read. A stream of major 1 is read at any minor version; one of a later minor
// is refused (Error kUnsupportedVersion, naming the chunk or feature) only where it uses what
// its minor version adds. A greater major, and the pre-release formats 1.0-9.3 (written by capz
// 0.1.0 and earlier, with the magic "\x89capz"), are refused (kUnsupportedVersion).
constexpr FormatVersion kFormatNewestRead{1, 1};

}  // namespace capz
