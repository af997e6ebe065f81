// Damaged streams of ragged frames (docs/FORMAT.md "Scans (format 1.1)"), made from the format
// 1.1 golden streams of data/scan_small: SCNW payload bytes changed under a recomputed CRC give
// a clean error or a well-formed take, never a crash or an unbounded allocation; a missing SCNW,
// one of another window, the ragged feature bit in a stream relabelled 1.0, frame counts that
// disagree with HEAD or with the chunk, and truncations (of the file, and of an SCNW payload
// re-framed with a valid CRC and index) are refused with a clean error naming the fault.
// Positions are sampled (every byte of the first 256, then a stride) so that each stream costs at
// most about 600 decodes: this suite also runs under ASan.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/tool/file.h"
#include "chunk_util.h"
#include "coding/bytes.h"
#include "coding/container.h"
#include "coding/crc32c.h"
#include "coding/scan_octree.h"
#include "test_util.h"

namespace capz {
namespace {

const std::string kStreams = std::string(CAPZ_TEST_DIR) + "/golden/streams/";
const char* const kOneWindow = "scan_small.grid1mm.v1.1.capz";      // 4 frames, 1 window
const char* const kTwoWindows = "scan_small.grid1cm-w2.v1.1.capz";  // 2 windows of 2 frames
const char* const kLossless = "scan_small.lossless.v1.1.capz";      // mode 2, a float32 split
const char* const kOctree = "scan_small.octree2cm.v1.1.capz";       // octree frames
const char* const kRaw64 = "utm_small.lossless-w2.v1.1.capz";       // mode 3: raw windows
const char* const kRaw32 = "depth_drop_small.lossless.v1.1.capz";   // mode 2: a raw window

// The positions to damage in a payload of n bytes, about `most` of them: all of the first 256
// (at most half of `most`), the last 16, and the rest spread evenly (payload_positions).
std::vector<size_t> sampled(size_t n, size_t most) {
  const size_t head = std::min<size_t>(256, most / 2), tail = 16;
  return capz_test::payload_positions(n, head, most - head - tail, tail);
}

// A stream as its file header and chunks, rebuilt with every chunk's length and CRC right and
// INDX recomputed: each window from its first chunk to its last (a window's chunks are those
// from its SCNW in the stream read, whatever they are renamed to).
struct Chunks {
  std::vector<uint8_t> header;  // the 15-byte file header
  std::vector<std::string> type;
  std::vector<std::vector<uint8_t>> payload;
  std::vector<int> window;  // per chunk: its window, -1 for the file-level chunks and INDX

  explicit Chunks(const std::vector<uint8_t>& b) : header(b.begin(), b.begin() + 15) {
    int w = -1;
    for (size_t off = 15; off + 12 <= b.size();) {
      const size_t n = capz_test::chunk_len(b, off);
      type.emplace_back(b.begin() + static_cast<long>(off), b.begin() + static_cast<long>(off) + 4);
      payload.emplace_back(b.begin() + static_cast<long>(off) + 8,
                           b.begin() + static_cast<long>(off + 8 + n));
      w += type.back() == "SCNW";
      window.push_back(type.back() == "INDX" ? -1 : w);
      off += 12 + n;
    }
  }
  // The index of the k-th chunk of type t.
  size_t find(const std::string& t, size_t k = 0) const {
    for (size_t i = 0; i < type.size(); ++i)
      if (type[i] == t && k-- == 0) return i;
    ADD_FAILURE() << "no chunk " << t;
    return 0;
  }
  void erase(size_t i) {
    type.erase(type.begin() + static_cast<long>(i));
    payload.erase(payload.begin() + static_cast<long>(i));
    window.erase(window.begin() + static_cast<long>(i));
  }
  std::vector<uint8_t> bytes() const {
    std::vector<uint8_t> out = header;
    std::vector<IndexEntry> index;
    int last = -1;
    for (size_t i = 0; i < type.size(); ++i) {
      if (type[i] == "INDX") {
        append_chunk(&out, "INDX", encode_index(index));
        continue;
      }
      const size_t at = out.size();
      append_chunk(&out, type[i].c_str(), payload[i]);
      if (window[i] < 0) continue;
      if (window[i] != last) index.push_back(IndexEntry{at, 0});
      last = window[i];
      index.back().bytes = out.size() - index.back().offset;
    }
    return out;
  }
};

// The code of the error decoding b gives, its text in *msg; -1 when b decodes.
int decode_code(const std::vector<uint8_t>& b, std::string* msg = nullptr) {
  try {
    decompress(b.data(), b.size(), "damaged.capz");
  } catch (const Error& e) {
    if (msg) *msg = e.what();
    return static_cast<int>(e.code());
  }
  return -1;
}

// b decodes to a well-formed take of ref's frame count, or throws a clean kCorrupt naming the
// file. Counts the errors.
void expect_caught_or_harmless(const std::vector<uint8_t>& b, const Take& ref, size_t* errors,
                               const std::string& where) {
  try {
    const Take t = decompress(b.data(), b.size(), "damaged.capz");
    ASSERT_EQ(t.frames, ref.frames) << where;
    ASSERT_TRUE(t.ragged()) << where;
    EXPECT_EQ(t.xyz.size(), t.total_points() * 3) << where;
    EXPECT_EQ(t.valid.size(), t.total_points()) << where;
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_EQ(e.code(), ErrorCode::kCorrupt) << where << ": " << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << where << ": " << m;
    EXPECT_NE(m.find("damaged.capz"), std::string::npos) << where << ": " << m;
    ++*errors;
  }
}

// Every sampled byte of each SCNW payload of `stream` changed by `flip` (CRC recomputed), about
// `most` decodes over the stream's windows.
void damage_scnw(const char* stream, uint8_t flip, size_t most = 600) {
  const std::vector<uint8_t> good = read_file(kStreams + stream);
  const Take ref = decompress(good.data(), good.size(), stream);
  std::vector<size_t> chunks;  // offsets of the SCNW chunks
  for (size_t at = 15; at + 12 <= good.size(); at += 12 + capz_test::chunk_len(good, at))
    if (std::equal(good.begin() + static_cast<long>(at), good.begin() + static_cast<long>(at) + 4,
                   "SCNW"))
      chunks.push_back(at);
  ASSERT_FALSE(chunks.empty());
  for (size_t at : chunks) {
    const size_t len = capz_test::chunk_len(good, at);
    size_t errors = 0;
    const std::vector<size_t> where = sampled(len, most / chunks.size());
    for (size_t i : where) {
      std::vector<uint8_t> b = good;
      b[at + 8 + i] ^= flip;
      capz_test::fix_crc(&b, at);
      expect_caught_or_harmless(b, ref, &errors,
                                std::string(stream) + " SCNW at " + std::to_string(at) +
                                    ", payload byte " + std::to_string(i));
    }
    // The window index, the total, the counts, flags and table are checked; a change inside the
    // coded residuals decodes to other points (the chunk CRC is what catches those).
    EXPECT_GT(errors, 0u) << stream << ": " << errors << " of " << where.size();
  }
}

TEST(ScanCorrupt, GivenEverySampledScnwByteDamagedThenCleanCorruptOrAWellFormedTake) {
  damage_scnw(kOneWindow, 0x01);
  damage_scnw(kTwoWindows, 0x80);
  damage_scnw(kLossless, 0x01, 80);  // with ATTR and the residue: slower decodes
  damage_scnw(kOctree, 0x01);
  damage_scnw(kOctree, 0x10);
  damage_scnw(kRaw64, 0x01, 120);  // "Raw windows": the counts, then the LZMA2 stream
  damage_scnw(kRaw32, 0x01, 80);
}

// "Octree frames": a stream whose SCNW holds octree frames without HEAD bit 6 is corrupt.
TEST(ScanCorrupt, GivenOctreeFramesWithoutHeadBit6ThenCorrupt) {
  Chunks c(read_file(kStreams + kOctree));
  ASSERT_EQ(c.payload[c.find("HEAD")][19] & 0x60, 0x60);
  c.payload[c.find("HEAD")][19] &= static_cast<uint8_t>(~0x40u);
  std::string msg;
  EXPECT_EQ(decode_code(c.bytes(), &msg), static_cast<int>(ErrorCode::kCorrupt)) << msg;
  EXPECT_NE(msg.find("octree frames in a stream without HEAD feature bit 6"), std::string::npos)
      << msg;
}

// "The block's flags": the octree golden (four Helios sweeps at 2 cm) takes the cones of its
// table, the counting models and the mix (L = 7), so the damage above reaches that path too.
TEST(ScanCorrupt, GivenTheOctreeGoldenThenItsBlockTakesTheConesCountingModelsAndMix) {
  const Chunks c(read_file(kStreams + kOctree));
  size_t cones = 0;
  for (size_t i = 0; i < c.type.size(); ++i) {
    if (c.type[i] != "SCNW") continue;
    ByteReader r(c.payload[i].data(), c.payload[i].size(), "SCNW");
    r.varint();  // window, total, gaps: mode 0 has no zeros, no split
    r.varint();
    r.u8();
    const uint8_t* g = c.payload[i].data() + r.offset();
    const size_t n = c.payload[i].size() - r.offset();
    const scan::Header h = scan::read_header(g, n, "SCNW", SIZE_MAX);
    if (h.octree_size == 0 || h.table.rings() == 0) continue;  // L = 0 without a table
    IntDecoder dec(g + h.octree, h.octree_size, scan::kOctreeContexts, "SCNW");
    const uint32_t l = dec.get(scan::kOctFlagsCtx);
    cones += l == 7;  // the sampled damage above reaches the mix (FORMAT.md "Mixing")
  }
  EXPECT_GT(cones, 0u);
}

// "Lossless ragged streams": SCNW's split exponent E and the geometry's length, then the
// corrections block (its own corruptions: tests/unit/test_scan_split.cpp).
TEST(ScanCorrupt, GivenADamagedFloat32SplitThenCorruptNamingScnw) {
  const Chunks good(read_file(kStreams + kLossless));
  const size_t scnw = good.find("SCNW");
  ByteReader r(good.payload[scnw].data(), good.payload[scnw].size(), "SCNW");
  r.varint();
  r.varint();
  ASSERT_EQ(r.u8(), 0);  // gaps: no origin points
  const size_t e_at = r.offset();
  const int e = static_cast<int8_t>(r.u8());
  ASSERT_GE(e, -64);  // the golden stream has a split
  ASSERT_LE(e, 64);
  const size_t len_at = r.offset();
  const uint64_t len = r.varint();
  const size_t geo_at = r.offset();
  ASSERT_LT(geo_at + len, good.payload[scnw].size());  // a corrections block follows
  std::string msg;
  for (const uint8_t bad : {uint8_t{65}, uint8_t{0xBF}, uint8_t{0x81}, uint8_t{0x7F}}) {
    Chunks c = good;
    c.payload[scnw][e_at] = bad;  // 65, -65, -127, 127: neither -128 nor in -64..64
    EXPECT_EQ(decode_code(c.bytes(), &msg), static_cast<int>(ErrorCode::kCorrupt)) << msg;
    EXPECT_NE(msg.find("SCNW"), std::string::npos) << msg;
    EXPECT_NE(msg.find("exponent"), std::string::npos) << msg;
  }
  // The geometry's length beyond the chunk, or one byte off either way.
  Chunks c = good;
  std::vector<uint8_t>& p = c.payload[scnw];
  ByteWriter w;
  w.varint(p.size());
  p.erase(p.begin() + static_cast<long>(len_at), p.begin() + static_cast<long>(geo_at));
  p.insert(p.begin() + static_cast<long>(len_at), w.buffer().begin(), w.buffer().end());
  EXPECT_EQ(decode_code(c.bytes(), &msg), static_cast<int>(ErrorCode::kCorrupt)) << msg;
  EXPECT_NE(msg.find("SCNW"), std::string::npos) << msg;
  for (const uint64_t other : {len - 1, len + 1}) {
    c = good;
    ByteWriter o;
    o.varint(other);
    std::vector<uint8_t>& q = c.payload[scnw];
    q.erase(q.begin() + static_cast<long>(len_at), q.begin() + static_cast<long>(geo_at));
    q.insert(q.begin() + static_cast<long>(len_at), o.buffer().begin(), o.buffer().end());
    EXPECT_EQ(decode_code(c.bytes(), &msg), static_cast<int>(ErrorCode::kCorrupt)) << other;
  }
  // The corrections block's last byte gone, or one byte more.
  c = good;
  c.payload[scnw].pop_back();
  EXPECT_EQ(decode_code(c.bytes(), &msg), static_cast<int>(ErrorCode::kCorrupt)) << msg;
  c = good;
  c.payload[scnw].push_back(0);
  EXPECT_EQ(decode_code(c.bytes(), &msg), static_cast<int>(ErrorCode::kCorrupt)) << msg;
}

TEST(ScanCorrupt, GivenAMissingScnwThenCorruptOrRefusedNamingIt) {
  for (const char* stream : {kOneWindow, kTwoWindows}) {
    SCOPED_TRACE(stream);
    const Chunks good(read_file(kStreams + stream));
    std::string msg;
    // The last window's renamed to an ancillary type (skipped): that window has no SCNW. In
    // window 0 the skipped chunk would stand among the file-level chunks (FORMAT.md 3.4), so
    // that window's index entry points before the first window: corrupt too.
    const bool two = std::string(stream) == kTwoWindows;
    Chunks c = good;
    c.type[c.find("SCNW", two ? 1 : 0)] = "sCNW";
    EXPECT_EQ(decode_code(c.bytes(), &msg), static_cast<int>(ErrorCode::kCorrupt)) << msg;
    EXPECT_NE(msg.find(two ? "SCNW" : "INDX entry of window 0"), std::string::npos) << msg;
    // Renamed to a critical type no decoder knows: a later version's chunk.
    c.type[c.find("sCNW")] = "QCNW";
    EXPECT_EQ(decode_code(c.bytes(), &msg), static_cast<int>(ErrorCode::kUnsupportedVersion))
        << msg;
    EXPECT_NE(msg.find("chunk QCNW of format 1.1"), std::string::npos) << msg;
    // Removed (the rebuilt index then lists a window less than HEAD implies).
    c = good;
    c.erase(c.find("SCNW"));
    EXPECT_EQ(decode_code(c.bytes(), &msg), static_cast<int>(ErrorCode::kCorrupt)) << msg;
    // A POSW in its place (HEAD still says ragged frames).
    c = good;
    c.type[c.find("SCNW")] = "POSW";
    EXPECT_EQ(decode_code(c.bytes(), &msg), static_cast<int>(ErrorCode::kCorrupt)) << msg;
  }
}

TEST(ScanCorrupt, GivenAnScnwOfAnotherWindowThenCorruptNamingIt) {
  const Chunks good(read_file(kStreams + kTwoWindows));
  const size_t w0 = good.find("SCNW", 0), w1 = good.find("SCNW", 1);
  ASSERT_EQ(good.payload[w0][0], 0);
  ASSERT_EQ(good.payload[w1][0], 1);
  std::string msg;
  for (const uint8_t w : {1, 2}) {  // window 0's chunk says window 1, then 2
    Chunks c = good;
    c.payload[w0][0] = w;
    EXPECT_EQ(decode_code(c.bytes(), &msg), static_cast<int>(ErrorCode::kCorrupt)) << msg;
    EXPECT_NE(msg.find("SCNW"), std::string::npos) << msg;
  }
  Chunks c = good;  // window 1's chunk says window 0
  c.payload[w1][0] = 0;
  EXPECT_EQ(decode_code(c.bytes(), &msg), static_cast<int>(ErrorCode::kCorrupt)) << msg;
  EXPECT_NE(msg.find("SCNW"), std::string::npos) << msg;
  // The two windows' chunks swapped, each with its own index: each stands in the other's place.
  c = good;
  std::swap(c.payload[w0], c.payload[w1]);
  EXPECT_EQ(decode_code(c.bytes(), &msg), static_cast<int>(ErrorCode::kCorrupt)) << msg;
  // Random access to the second window alone meets window 0's chunk there too.
  const std::vector<uint8_t> b = c.bytes();
  EXPECT_EQ(capz_test::error_of([&] { decompress_frames(b.data(), b.size(), 2, 2, "x"); }, &msg),
            ErrorCode::kCorrupt)
      << msg;
}

// The file header's minor byte set to 0 (its CRC made right): HEAD's bit 3 in a 1.0 stream.
TEST(ScanCorrupt, GivenTheRaggedBitInAStreamOfMinorVersion0ThenCorrupt) {
  std::vector<uint8_t> b = read_file(kStreams + kOneWindow);
  ASSERT_EQ(b[10], kFormatScans.minor);
  b[10] = 0;
  const uint32_t crc = crc32c(b.data(), 11);
  for (int k = 0; k < 4; ++k) b[11 + static_cast<size_t>(k)] = static_cast<uint8_t>(crc >> (8 * k));
  std::string msg;
  EXPECT_EQ(decode_code(b, &msg), static_cast<int>(ErrorCode::kCorrupt)) << msg;
  EXPECT_NE(msg.find("feature bit 3 (ragged frames) in a format 1.0 stream"), std::string::npos)
      << msg;
  EXPECT_EQ(capz_test::error_of([&] { describe(b.data(), b.size(), "x"); }), ErrorCode::kCorrupt);
  // The other way: a 1.1 stream whose HEAD lost bit 3 has SCNW where POSW belongs.
  Chunks c(read_file(kStreams + kOneWindow));
  c.payload[c.find("HEAD")][19] &= static_cast<uint8_t>(~0x08u);
  EXPECT_NE(decode_code(c.bytes(), &msg), -1);
}

// HEAD's bit 5, points reordered (FORMAT.md "Points reordered"): without bit 3 or with bit 0 it
// is corrupt; on a stream coded in file order it changes nothing but what describe says (the
// decoder needs no permutation); a feature bit this decoder does not know (7) is refused by name,
// as a decoder that does not know bit 5 refuses a reordered stream.
TEST(ScanCorrupt, GivenThePointsReorderedBitWhereItDoesNotBelongThenCorruptOrRefused) {
  const Chunks any(read_file(kStreams + std::string("scan_small.any1mm.v1.1.capz")));
  ASSERT_EQ(any.payload[any.find("HEAD")][19] & 0x28, 0x28);
  std::string msg;
  for (uint8_t change : {uint8_t{0x08}, uint8_t{0x01}}) {  // bit 3 cleared, bit 0 set
    Chunks c = any;
    c.payload[c.find("HEAD")][19] ^= change;
    EXPECT_EQ(decode_code(c.bytes(), &msg), static_cast<int>(ErrorCode::kCorrupt)) << msg;
    EXPECT_NE(msg.find("feature bit 5 (points reordered) without ragged frames or with lossless"),
              std::string::npos)
        << msg;
  }
  Chunks kept(read_file(kStreams + kOneWindow));
  const std::vector<uint8_t> plain = kept.bytes();
  kept.payload[kept.find("HEAD")][19] |= 0x20;
  const std::vector<uint8_t> b = kept.bytes();
  EXPECT_TRUE(describe(b.data(), b.size(), "x").points_reordered);
  EXPECT_FALSE(describe(plain.data(), plain.size(), "x").points_reordered);
  EXPECT_EQ(decompress(b.data(), b.size()).xyz, decompress(plain.data(), plain.size()).xyz);
  Chunks later = any;
  later.payload[later.find("HEAD")][19] |= 0x80;
  EXPECT_EQ(decode_code(later.bytes(), &msg), static_cast<int>(ErrorCode::kUnsupportedVersion))
      << msg;
  EXPECT_NE(msg.find("feature bit 7 of format 1.1 is not known to this decoder"), std::string::npos)
      << msg;
  // Bit 6 (octree frames) only with bit 5 (points reordered).
  Chunks octree = Chunks(read_file(kStreams + kOneWindow));
  octree.payload[octree.find("HEAD")][19] |= 0x40;
  EXPECT_EQ(decode_code(octree.bytes(), &msg), static_cast<int>(ErrorCode::kCorrupt)) << msg;
  EXPECT_NE(msg.find("feature bit 6 (octree frames) without points reordered"), std::string::npos)
      << msg;
}

// HEAD's frame count (u64 at payload byte 0) off by one either way, and the counts inside SCNW
// (the payload's F and a frame's n_f) changed: corrupt, before any point is decoded for HEAD.
TEST(ScanCorrupt, GivenFrameCountsDisagreeingWithHeadThenCorrupt) {
  for (const char* stream : {kOneWindow, kTwoWindows}) {
    SCOPED_TRACE(stream);
    const Chunks good(read_file(kStreams + stream));
    const size_t head = good.find("HEAD"), scnw = good.find("SCNW");
    ASSERT_EQ(good.payload[head][0], 4);
    std::string msg;
    for (const uint8_t frames : {3, 5, 1}) {
      Chunks c = good;
      c.payload[head][0] = frames;
      EXPECT_EQ(decode_code(c.bytes(), &msg), static_cast<int>(ErrorCode::kCorrupt))
          << int(frames) << ": " << msg;
    }
    // SCNW payload: window, total (varints), gaps (u8), then F and the n_f (varints).
    ByteReader r(good.payload[scnw].data(), good.payload[scnw].size(), "SCNW");
    r.varint();
    const uint64_t total = r.varint();
    EXPECT_EQ(r.u8(), 0);  // gaps
    const size_t f_at = r.offset();
    const uint64_t F = r.varint();
    const size_t n0_at = r.offset();
    EXPECT_EQ(F, good.payload[head][12] == 2 ? 2u : 4u);  // HEAD window_frames (u32 at 12)
    EXPECT_LT(total, uint64_t{1} << 21);
    Chunks c = good;
    c.payload[scnw][f_at] = static_cast<uint8_t>(F + 1);
    EXPECT_EQ(decode_code(c.bytes(), &msg), static_cast<int>(ErrorCode::kCorrupt)) << msg;
    EXPECT_NE(msg.find("SCNW"), std::string::npos) << msg;
    c = good;
    c.payload[scnw][f_at] = static_cast<uint8_t>(F - 1);
    EXPECT_EQ(decode_code(c.bytes(), &msg), static_cast<int>(ErrorCode::kCorrupt)) << msg;
    c = good;
    c.payload[scnw][n0_at] ^= 1;  // the first frame's count: the sum is no longer the total
    EXPECT_EQ(decode_code(c.bytes(), &msg), static_cast<int>(ErrorCode::kCorrupt)) << msg;
    EXPECT_NE(msg.find("SCNW"), std::string::npos) << msg;
    EXPECT_NE(msg.find("total"), std::string::npos) << msg;
    // HEAD's point count must be 0 in a stream of ragged frames.
    c = good;
    c.payload[head][8] = 7;
    EXPECT_EQ(decode_code(c.bytes(), &msg), static_cast<int>(ErrorCode::kCorrupt)) << msg;
  }
}

// Frames of one organized shape (FORMAT.md "Ragged frames: HEAD and the window chunk"): in the
// lidar_small golden stream (META's layout 512 x 1, 6 frames of 512 points in one window) the
// first frame's count made 511 and the second's 513, the sum still the chunk's total: corrupt,
// naming SCNW and the shape, for decompress and describe alike.
TEST(ScanCorrupt, GivenAFrameCountThatIsNotTheOrganizedShapeThenCorrupt) {
  const Chunks good(read_file(kStreams + std::string("lidar_small.grid0.01.v1.1.capz")));
  const size_t scnw = good.find("SCNW");
  std::string msg;
  ASSERT_EQ(decode_code(good.bytes(), &msg), -1) << msg;
  ByteReader r(good.payload[scnw].data(), good.payload[scnw].size(), "SCNW");
  r.varint();
  ASSERT_EQ(r.varint(), 6u * 512u);  // total
  ASSERT_EQ(r.u8(), 0);              // gaps
  ASSERT_EQ(r.varint(), 6u);         // F
  const size_t n0_at = r.offset();
  ASSERT_EQ(r.varint(), 512u);
  const size_t n1_at = r.offset();
  ASSERT_EQ(r.varint(), 512u);
  ASSERT_EQ(r.offset(), n1_at + 2);  // 512 = 0x80 0x04; 511 = 0xff 0x03, 513 = 0x81 0x04
  Chunks c = good;
  c.payload[scnw][n0_at] = 0xff;
  c.payload[scnw][n0_at + 1] = 0x03;
  c.payload[scnw][n1_at] = 0x81;
  const std::vector<uint8_t> b = c.bytes();
  EXPECT_EQ(decode_code(b, &msg), static_cast<int>(ErrorCode::kCorrupt)) << msg;
  EXPECT_NE(msg.find("SCNW"), std::string::npos) << msg;
  EXPECT_NE(msg.find("511 points"), std::string::npos) << msg;
  EXPECT_NE(msg.find("512 x 1"), std::string::npos) << msg;
  try {
    describe(b.data(), b.size(), "damaged.capz");
    ADD_FAILURE() << "describe took a frame count that is not the shape";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kCorrupt) << e.what();
  }
}

// The file cut short anywhere (sampled), and each SCNW payload cut short inside a chunk whose
// length, CRC and index are right: a clean corrupt error, never a take.
TEST(ScanCorrupt, GivenTruncationsThenCorrupt) {
  for (const char* stream : {kOneWindow, kTwoWindows, kLossless, kRaw64, kRaw32}) {
    SCOPED_TRACE(stream);
    const std::vector<uint8_t> good = read_file(kStreams + stream);
    for (size_t n : sampled(good.size(), 300)) {
      std::string msg;
      const int code = [&] {
        try {
          decompress(good.data(), n, "cut.capz");
        } catch (const Error& e) {
          msg = e.what();
          return static_cast<int>(e.code());
        }
        return -1;
      }();
      // Without \\x89CAPZ whole, the bytes are not recognisably a .capz (FORMAT.md 3.1).
      const ErrorCode want = n < 5 ? ErrorCode::kNotOurFormat : ErrorCode::kCorrupt;
      EXPECT_EQ(code, static_cast<int>(want)) << n << " bytes: " << msg;
    }
    const Chunks whole(good);
    const size_t windows =
        static_cast<size_t>(std::count(whole.type.begin(), whole.type.end(), "SCNW"));
    for (size_t k = 0; k < windows; ++k) {
      const size_t at = whole.find("SCNW", k);
      const size_t len = whole.payload[at].size();
      for (size_t n : sampled(len, 300 / windows)) {  // n = len - 1 (one byte short) included
        Chunks c = whole;
        c.payload[at].resize(n);
        std::string msg;
        EXPECT_EQ(decode_code(c.bytes(), &msg), static_cast<int>(ErrorCode::kCorrupt))
            << "SCNW " << k << " cut to " << n << " of " << len << ": " << msg;
      }
      // One byte appended to the payload: not consumed exactly.
      Chunks c = whole;
      c.payload[at].push_back(0);
      std::string msg;
      EXPECT_EQ(decode_code(c.bytes(), &msg), static_cast<int>(ErrorCode::kCorrupt)) << msg;
    }
  }
}

// The rebuilt stream without changes decodes as the golden one does (the helper is right).
TEST(ScanCorrupt, GivenTheRebuiltGoldenStreamThenItIsByteIdentical) {
  for (const char* stream : {kOneWindow, kTwoWindows, kLossless, kRaw64, kRaw32}) {
    const std::vector<uint8_t> good = read_file(kStreams + stream);
    EXPECT_TRUE(Chunks(good).bytes() == good) << stream;
  }
}

// "Raw windows": a raw window's gaps byte with origin points or another bit, a mode 3 window
// that is not raw, another frame count, counts that do not sum to `total`: corrupt, naming SCNW.
TEST(ScanCorrupt, GivenARawWindowsHeaderChangedThenCorruptNamingScnw) {
  for (const char* stream : {kRaw64, kRaw32}) {
    const Chunks good(read_file(kStreams + stream));
    const size_t scnw = good.find("SCNW");
    ByteReader r(good.payload[scnw].data(), good.payload[scnw].size(), "SCNW");
    r.varint();  // window, total
    r.varint();
    const size_t gaps = r.offset();
    ASSERT_EQ(good.payload[scnw][gaps], 2) << stream;
    const bool f64 = stream == std::string(kRaw64);
    std::vector<std::pair<size_t, uint8_t>> bad = {{gaps, 3}, {gaps, 6}, {gaps + 1, 1}};
    if (f64) bad.push_back({gaps, 0});                            // mode 3, not raw
    bad.push_back({gaps + 2, good.payload[scnw][gaps + 2] ^ 1});  // frame 0's count
    for (const auto& b : bad) {
      Chunks c = good;
      c.payload[scnw][b.first] = b.second;
      std::string msg;
      EXPECT_EQ(decode_code(c.bytes(), &msg), static_cast<int>(ErrorCode::kCorrupt))
          << stream << " byte " << b.first << " = " << int(b.second) << ": " << msg;
      EXPECT_NE(msg.find("SCNW"), std::string::npos) << msg;
    }
  }
}

// HEAD: ragged frames in mode 3 without the lossless bit are corrupt ("Raw windows").
TEST(ScanCorrupt, GivenRaggedMode3WithoutLosslessThenCorrupt) {
  Chunks c(read_file(kStreams + kRaw64));
  ASSERT_EQ(c.payload[c.find("HEAD")][19] & 0x09, 0x09);  // ragged, lossless
  c.payload[c.find("HEAD")][19] &= static_cast<uint8_t>(~0x01u);
  std::string msg;
  EXPECT_EQ(decode_code(c.bytes(), &msg), static_cast<int>(ErrorCode::kCorrupt)) << msg;
  EXPECT_NE(msg.find("position mode 3 without lossless"), std::string::npos) << msg;
}

}  // namespace
}  // namespace capz
