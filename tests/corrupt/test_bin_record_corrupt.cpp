// HEAD's frame_format of a .bin folder (FORMAT.md "Frame-file sources"): 6 says META's fields
// after x y z are a declared record, any fields; 4 says the names' record, whose fields are those
// of the frame names or none. A stream whose frame_format is changed (its CRC fixed) decodes as
// the new value says, or fails as corrupt naming the fault, never as another take silently.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/tool/file.h"
#include "chunk_util.h"
#include "support/stream_pieces.h"

namespace {

const std::string kStreams = std::string(CAPZ_TEST_DIR) + "/golden/streams/";

// Stream `name` with HEAD's last byte (frame_format) set to v, its CRC fixed; *was gets the old.
std::vector<uint8_t> with_frame_format(const std::string& name, uint8_t v, uint8_t* was) {
  std::vector<uint8_t> b = capz::read_file(kStreams + name);
  const size_t at = capz_test::find_chunk(b, "HEAD");
  EXPECT_NE(at, std::string::npos);
  const size_t last = at + 8 + capz_test::chunk_len(b, at) - 1;
  *was = b[last];
  b[last] = v;
  capz_test::fix_crc(&b, at);
  return b;
}

}  // namespace

TEST(BinRecordCorrupt, GivenADeclaredRecordsFrameFormatChangedThenCorruptOrTheRecordItSays) {
  uint8_t was = 0;
  // A declared record (x y z intensity:U1 _:U1 ring:U2 t:U4) under frame_format 4: its fields
  // are not KITTI's, whose names these are.
  std::vector<uint8_t> b = with_frame_format("scan_small_rec.grid1mm.v1.1.capz", 4, &was);
  EXPECT_EQ(was, 6);
  std::string why = capz_test::decode_error(b);
  EXPECT_NE(why.find("not those of its record"), std::string::npos) << why;
  b = with_frame_format("scan_small_rec.grid1mm.v1.1.capz", 7, &was);
  why = capz_test::decode_error(b);
  EXPECT_NE(why.find("unknown frame-file format 7"), std::string::npos) << why;
  // nuScenes' record under frame_format 6: a declared record of the same fields, which decodes.
  b = with_frame_format("scan_small_nus.grid1mm.v1.1.capz", 6, &was);
  EXPECT_EQ(was, 4);
  const capz::Take d = capz::decompress(b.data(), b.size(), "s.capz");
  ASSERT_TRUE(d.bin);
  EXPECT_TRUE(d.bin->declared);
  EXPECT_EQ(capz::bin_record_text(capz::bin_record_of(d)), "x y z intensity ring");
}
