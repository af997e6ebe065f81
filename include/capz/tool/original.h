// NOT PART OF THE STABLE API (include/capz/tool/): what the capz CLI and the Python module share
// so that they behave alike. Installed for programs that want the CLI's exact behaviour, but it
// may change in any release; the stable API is the headers of include/capz/ itself.
// capz — the original file a .capz records (docs/FORMAT.md 7, 14): its size and XXH3-128 hash
// (chunk HASH) and the residue that rebuilds it from the decoded take (C3DR/C3DP, TRCR/TRCP).
#pragma once

#include <cstdint>
#include <string>

#include "capz/codec.h"  // DecompressOptions

namespace capz {

struct OriginalInfo {
  bool hashed = false;   // the archive carries HASH
  uint64_t size = 0;     // the original's bytes (hashed only)
  std::string hash_hex;  // 32 hex digits (hashed only)
  bool residue = false;  // and a file-level residue (C3DR or TRCR)
  bool exact = false;    // and lossless: the original comes back byte for byte, hash checked
  // and a per-window residue at any target (format 5.0 on): at a bound everything but the
  // coordinates comes back as the file holds it (a 4.0 archive has it for C3D only)
  bool windows_at_bound = false;
};

// Reads HEAD, META and the file-level chunks of `capz_path`. Throws capz::Error.
OriginalInfo original_info(const std::string& capz_path);

// True when rebuild_original can write the original's own format from this archive: a residue,
// and lossless, a C3D, or a 5.0 archive (a 4.0 TRC at a bound goes through the TRC writer).
bool can_rebuild(const OriginalInfo& info, bool c3d);

// Rebuilds the original file from `capz_path` into `out` (written atomically, window by window):
// lossless, byte for byte with the size and hash checked before the output is renamed into
// place; at a bound, the original head and tail around frames regenerated from the decoded
// coordinates (a C3D: its size checked; a TRC: coordinates printed with the source's decimals). A
// mismatch is Error(kCorrupt) naming the archive, and no output is left. opts.threads: windows
// decoded in parallel (the output is the same).
void rebuild_original(const std::string& capz_path, const std::string& out, bool overwrite,
                      const DecompressOptions& opts = {});

// The same rebuild, written nowhere: checks size and hash (lossless) or size (bound).
void test_original(const std::string& capz_path, const DecompressOptions& opts = {});

// For --rm and verify --against: "" when `capz_path` is exact and its rebuilt bytes (size and
// hash checked: Error(kCorrupt) when they differ) hash as the file at `original` does now (a
// folder of frames: its frame files concatenated in frame order); else what differs.
std::string rebuilds_file(const std::string& capz_path, const std::string& original,
                          const DecompressOptions& opts = {});

}  // namespace capz
