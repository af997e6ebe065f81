// PCD frames with fields other than x y z (issue #15): the reader keeps every field's bytes and
// the layout, the writer gives back the same fields, types, order and organization, the
// archive keeps them lossless at every target, and nothing is dropped without being asked.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/io.h"
#include "capz/stream.h"
#include "capz/tool/file.h"
#include "capz/tool/original.h"
#include "capz/tool/verify.h"
#include "test_util.h"

namespace fs = std::filesystem;
using capz::ErrorCode;
using capz_test::TempDir;

namespace {

// A scan-like frame layout: organized W x H, float32 x y z, packed float rgb, float intensity,
// three normals, a uint16 label, a 4-float descriptor (COUNT 4), an int8 padding field.
constexpr size_t kW = 8, kH = 6, kN = kW * kH;
const char* kFields = "x y z rgb intensity normal_x normal_y normal_z label desc _";
const char* kSizes = "4 4 4 4 4 4 4 4 2 4 1";
const char* kTypes = "F F F F F F F F U F I";
const char* kCounts = "1 1 1 1 1 1 1 1 1 4 1";
constexpr size_t kStep = 4 * 8 + 2 + 16 + 1;

void put(std::vector<uint8_t>* b, const void* p, size_t n) {
  const auto* c = static_cast<const uint8_t*>(p);
  b->insert(b->end(), c, c + n);
}

// One frame's body (binary): smooth positions with a NaN hole, colour, intensity from the
// distance, normals, labels, descriptors.
std::vector<uint8_t> frame_body(size_t f) {
  std::vector<uint8_t> b;
  for (size_t p = 0; p < kN; ++p) {
    const float col = static_cast<float>(p % kW), row = static_cast<float>(p / kW);
    float xyz[3] = {col * 0.01f, row * 0.01f,
                    1.0f + 0.001f * static_cast<float>(f) + col * row * 1e-4f};
    if (p == 10 || (f == 1 && p == 20)) xyz[0] = xyz[1] = xyz[2] = std::nanf("");
    put(&b, xyz, 12);
    const uint32_t rgb = (static_cast<uint32_t>(p * 5 % 256) << 16) |
                         (static_cast<uint32_t>(row * 40) << 8) | static_cast<uint32_t>(f * 30);
    put(&b, &rgb, 4);
    const float intensity = p == 7 ? std::nanf("") : 100.0f / (1.0f + static_cast<float>(p));
    put(&b, &intensity, 4);
    const float n[3] = {0.0f, -0.0f, 1.0f - static_cast<float>(f) * 0.125f};
    put(&b, n, 12);
    const uint16_t label = static_cast<uint16_t>(p / 16 + 1000);
    put(&b, &label, 2);
    const float desc[4] = {1.5f, static_cast<float>(p), -2.0f, static_cast<float>(f)};
    put(&b, desc, 16);
    const int8_t pad = static_cast<int8_t>(-static_cast<int>(p % 3));
    put(&b, &pad, 1);
  }
  return b;
}

void write_frame(const fs::path& file, size_t f, const std::string& viewpoint = "1 2 3 1 0 0 0") {
  std::ofstream o(file, std::ios::binary);
  o << "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS " << kFields << "\nSIZE "
    << kSizes << "\nTYPE " << kTypes << "\nCOUNT " << kCounts << "\nWIDTH " << kW << "\nHEIGHT "
    << kH << "\nVIEWPOINT " << viewpoint << "\nPOINTS " << kN << "\nDATA binary\n";
  const std::vector<uint8_t> body = frame_body(f);
  o.write(reinterpret_cast<const char*>(body.data()), static_cast<std::streamsize>(body.size()));
}

std::string make_scan_folder(const TempDir& d, size_t frames = 3) {
  const std::string dir = d.file("scan");
  fs::create_directory(dir);
  for (size_t f = 0; f < frames; ++f)
    write_frame(fs::path(dir) / ("frame_" + std::to_string(f) + ".pcd"), f);
  return dir;
}

// A frame file's header lines (up to DATA) and its body.
void split_file(const std::string& path, std::string* header, std::vector<uint8_t>* body) {
  std::vector<uint8_t> bytes = capz::read_file(path);
  std::string text(bytes.begin(), bytes.end());
  const size_t d = text.find("DATA ");
  const size_t e = text.find('\n', d);
  *header = text.substr(0, e + 1);
  body->assign(bytes.begin() + static_cast<long>(e + 1), bytes.end());
}

std::string header_line(const std::string& header, const std::string& key) {
  std::istringstream is(header);
  std::string line;
  while (std::getline(is, line))
    if (line.rfind(key + " ", 0) == 0) return line;
  return "";
}

void expect_fields_as_source(const capz::Take& t) {
  ASSERT_EQ(t.attributes.size(), 8u);
  const char* names[] = {"rgb",      "intensity", "normal_x", "normal_y",
                         "normal_z", "label",     "desc",     "_"};
  for (size_t a = 0; a < 8; ++a) EXPECT_EQ(t.attributes[a].name, names[a]);
  EXPECT_EQ(t.attributes[5].type, 'U');
  EXPECT_EQ(t.attributes[5].size, 2);
  EXPECT_EQ(t.attributes[6].count, 4);
  EXPECT_EQ(t.attributes[7].type, 'I');
  ASSERT_TRUE(t.pcd);
  EXPECT_EQ(t.pcd->width, kW);
  EXPECT_EQ(t.pcd->height, kH);
  EXPECT_EQ(t.pcd->fields.size(), 11u);
  EXPECT_EQ(t.pcd->fields[0].size, 4);
  EXPECT_EQ(t.pcd->viewpoint, (std::vector<double>{1, 2, 3, 1, 0, 0, 0}));
}

}  // namespace

TEST(PcdFields, ReaderKeepsEveryFieldsBytesAndTheLayout) {
  TempDir d;
  const std::string dir = make_scan_folder(d);
  capz::Take t = capz::read_pcd_folder(dir);
  expect_fields_as_source(t);
  EXPECT_EQ(t.frames, 3u);
  EXPECT_EQ(t.points, kN);
  EXPECT_FALSE(t.is_valid(0, 10));
  EXPECT_FALSE(t.is_valid(1, 20));
  EXPECT_TRUE(t.is_valid(0, 20));
  // Each field's bytes are the file's bytes for that field, point after point.
  for (size_t f = 0; f < 3; ++f) {
    const std::vector<uint8_t> body = frame_body(f);
    for (size_t p = 0; p < kN; ++p) {
      EXPECT_EQ(std::memcmp(&t.attributes[0].data[(f * kN + p) * 4], &body[p * kStep + 12], 4), 0);
      EXPECT_EQ(std::memcmp(&t.attributes[6].data[(f * kN + p) * 16], &body[p * kStep + 34], 16),
                0);
      EXPECT_EQ(t.attributes[7].data[f * kN + p], body[p * kStep + 50]);
    }
  }
  EXPECT_EQ(capz::field_names(t), "rgb, intensity, normal_x, normal_y, normal_z, label, desc, _");
}

TEST(PcdFields, FramesMustShareTheirFields) {
  TempDir d;
  const std::string dir = make_scan_folder(d, 2);
  std::ofstream o(fs::path(dir) / "frame_2.pcd");
  o << "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH " << kN
    << "\nHEIGHT 1\nPOINTS " << kN << "\nDATA ascii\n";
  for (size_t p = 0; p < kN; ++p) o << "1 2 3\n";
  o.close();
  std::string msg;
  EXPECT_EQ(capz_test::error_of([&] { capz::read_pcd_folder(dir); }, &msg), ErrorCode::kCorrupt);
  EXPECT_NE(msg.find("frame_2.pcd"), std::string::npos) << msg;
  EXPECT_NE(msg.find("other fields"), std::string::npos) << msg;
}

TEST(PcdFields, WriterGivesBackTheSameFieldsTypesAndOrganization) {
  TempDir d;
  const std::string dir = make_scan_folder(d);
  capz::Take t = capz::read_pcd_folder(dir);
  for (const char* enc : {"binary", "ascii", "binary_compressed"}) {
    const std::string out = d.file(std::string("out_") + enc);
    capz::WriteOptions wo;
    wo.pcd_encoding = enc;
    capz::write_pcd_folder(t, out, wo);
    std::string h, src_h;
    std::vector<uint8_t> body, src_body;
    split_file(out + "/frame_1.pcd", &h, &body);
    split_file(dir + "/frame_1.pcd", &src_h, &src_body);
    const bool ascii = std::string(enc) == "ascii";
    for (const char* key : {"WIDTH", "HEIGHT", "POINTS"})
      EXPECT_EQ(header_line(h, key), header_line(src_h, key)) << enc << " " << key;
    // ASCII writes packed colour as an unsigned integer (its alpha-255 patterns are NaNs).
    if (ascii) {
      EXPECT_EQ(header_line(h, "TYPE"), "TYPE F F F U F F F F U F");
    }
    EXPECT_EQ(header_line(h, "VIEWPOINT"), "VIEWPOINT 1 2 3 1 0 0 0") << enc;
    if (std::string(enc) == "binary") {
      EXPECT_EQ(h, src_h);
      EXPECT_EQ(body, src_body);
    }
    capz::Take back = capz::read_pcd_folder(out);
    capz_test::expect_same_samples(t, back);
    if (std::string(enc) != "binary") {
      // Padding is binary-only: the other encodings leave "_" out.
      ASSERT_EQ(back.attributes.size(), 7u);
      EXPECT_EQ(header_line(h, "FIELDS"),
                "FIELDS x y z rgb intensity normal_x normal_y normal_z label desc");
      capz::PointAttribute pad = t.attributes[7];
      back.attributes.push_back(pad);
      back.pcd->fields.push_back(t.pcd->fields[10]);
      if (ascii) back.attributes[0].type = 'F', back.pcd->fields[3].type = 'F';
    }
    expect_fields_as_source(back);
    for (size_t a = 0; a < t.attributes.size(); ++a)
      EXPECT_EQ(back.attributes[a].data, t.attributes[a].data)
          << enc << " " << t.attributes[a].name;
  }
  // Without a WriteOptions encoding, the source's.
  capz::write_pcd_folder(t, d.file("default"));
  std::string h;
  std::vector<uint8_t> body;
  split_file(d.file("default") + "/frame_0.pcd", &h, &body);
  EXPECT_EQ(header_line(h, "DATA"), "DATA binary");
}

TEST(PcdFields, ArchivesKeepEveryFieldLosslessAtEveryTarget) {
  TempDir d;
  const std::string dir = make_scan_folder(d, 5);
  capz::Take t = capz::read_pcd_folder(dir);
  for (int target = 0; target < 3; ++target) {
    capz::CompressOptions o;
    if (target == 0) o.lossless = true;
    if (target == 1) o.max_error = 1e-3;
    if (target == 2) o.window_frames = 2, o.max_error = 1e-4;
    capz::CompressStats st;
    const std::vector<uint8_t> z = capz::compress(t, o, &st);
    EXPECT_GT(st.attribute_bytes, 0u);
    capz::Take back = capz::decompress(z.data(), z.size(), "test");
    expect_fields_as_source(back);
    for (size_t a = 0; a < t.attributes.size(); ++a)
      EXPECT_EQ(back.attributes[a].data, t.attributes[a].data)
          << target << " " << t.attributes[a].name;
    // A range of frames gets the fields of those frames.
    capz::Take part = capz::decompress_frames(z.data(), z.size(), 1, 3, "test");
    ASSERT_EQ(part.attributes.size(), t.attributes.size());
    const size_t bpp = t.attributes[6].bytes_per_point();
    EXPECT_TRUE(std::equal(part.attributes[6].data.begin(), part.attributes[6].data.end(),
                           t.attributes[6].data.begin() + static_cast<long>(kN * bpp)));
    // Written back as float32 frames within the bound, every field as the source's.
    const std::string out = d.file("back" + std::to_string(target));
    capz::write_pcd_folder(back, out);
    capz::Take again = capz::read_pcd_folder(out);
    expect_fields_as_source(again);
    for (size_t i = 0; i < t.frames * t.points; ++i) {
      ASSERT_EQ(again.valid[i], t.valid[i]);
      if (!t.valid[i]) continue;
      for (int k = 0; k < 3; ++k) {
        const double e = std::fabs(again.xyz[i * 3 + k] - t.xyz[i * 3 + k]);
        if (target == 0)
          EXPECT_EQ(e, 0.0);
        else
          EXPECT_LE(e, o.max_error) << target;
      }
    }
  }
}

TEST(PcdFields, StreamingCompressionOfTheFolderGivesTheSameBytes) {
  TempDir d;
  const std::string dir = make_scan_folder(d, 4);
  capz::Take t = capz::read_pcd_folder(dir);
  capz::CompressOptions o;
  o.lossless = true;
  const std::vector<uint8_t> whole = capz::compress(t, o);
  const std::string z = d.file("s.capz");
  // The folder's source as the streaming coder sees it, without original_file(): the same bytes
  // as compress(). (With it, a lossless archive adds HASH, PCDR and PCDP: FORMAT.md 7.3, 14.3.)
  struct NoOriginal : capz::FrameSource {
    explicit NoOriginal(capz::FrameSource& in) : in_(in) { header_ = in.header(); }
    bool has_sample_words() const override { return in_.has_sample_words(); }
    void read(size_t first, size_t count, capz::FrameBlock* out) override {
      in_.read(first, count, out);
    }
    capz::FrameSource& in_;
  };
  std::unique_ptr<capz::FrameSource> src = capz::open_frames(dir);
  NoOriginal plain(*src);
  capz::compress_stream(plain, o, z, false, nullptr);
  EXPECT_EQ(capz::read_file(z), whole);
  // From the folder itself: the same take, byte-exact.
  std::unique_ptr<capz::FrameSource> src2 = capz::open_frames(dir);
  capz::compress_stream(*src2, o, z, true, nullptr);
  EXPECT_TRUE(capz::original_info(z).exact);
  const std::vector<uint8_t> b = capz::read_file(z);
  const capz::Take back = capz::decompress(b.data(), b.size());
  EXPECT_EQ(back.valid, t.valid);
  EXPECT_EQ(back.xyz, t.xyz);
}

TEST(PcdFields, NothingIsDroppedWithoutBeingAsked) {
  TempDir d;
  const std::string dir = make_scan_folder(d, 2);
  capz::Take t = capz::read_pcd_folder(dir);
  for (const char* name : {"a.c3d", "a.trc"}) {
    std::string msg;
    EXPECT_EQ(capz_test::error_of([&] { capz::write_take(t, d.file(name)); }, &msg),
              ErrorCode::kUsage);
    EXPECT_NE(msg.find("rgb, intensity"), std::string::npos) << msg;
    EXPECT_NE(msg.find("--drop-fields"), std::string::npos) << msg;
    EXPECT_FALSE(fs::exists(d.file(name)));
  }
  t.rate = 30;
  t.units = "m";
  capz::WriteOptions wo;
  wo.drop_fields = true;
  capz::write_take(t, d.file("a.c3d"), wo);
  capz::Take c = capz::read_take(d.file("a.c3d"));
  EXPECT_TRUE(c.attributes.empty());
  EXPECT_EQ(c.points, kN);
  // An archive drops them only when told to.
  capz::CompressOptions o;
  o.lossless = true;
  o.drop_fields = true;
  const std::vector<uint8_t> z = capz::compress(t, o);
  capz::Take back = capz::decompress(z.data(), z.size(), "test");
  EXPECT_TRUE(back.attributes.empty());
  capz_test::expect_same_samples(t, back);
}

TEST(PcdFields, TakesBuiltInMemoryKeepTheirFieldsToo) {
  capz::Take t;
  t.resize(3, 4);
  for (size_t i = 0; i < 12; ++i) {
    t.valid[i] = 1;
    t.xyz[i * 3] = static_cast<double>(i) * 0.1;
  }
  t.units = "mm";
  capz::PointAttribute a;
  a.name = "ring";
  a.type = 'U';
  a.size = 2;
  for (size_t i = 0; i < 12; ++i) {
    a.data.push_back(static_cast<uint8_t>(i % 4));
    a.data.push_back(0);
  }
  t.attributes.push_back(a);
  capz::CompressOptions o;
  o.max_error = 0.01;
  const std::vector<uint8_t> z = capz::compress(t, o);
  capz::Take back = capz::decompress(z.data(), z.size(), "test");
  ASSERT_EQ(back.attributes.size(), 1u);
  EXPECT_EQ(back.attributes[0].name, "ring");
  EXPECT_EQ(back.attributes[0].data, a.data);
  // A field with a bad type is refused, naming it.
  t.attributes[0].type = 'Q';
  std::string msg;
  EXPECT_EQ(capz_test::error_of([&] { capz::compress(t, o); }, &msg), ErrorCode::kInvalidParameter);
  EXPECT_NE(msg.find("ring"), std::string::npos) << msg;
}

TEST(PcdFields, FloatFieldsWithinTheirOwnBound) {
  TempDir d;
  const std::string dir = make_scan_folder(d, 4);
  capz::Take t = capz::read_pcd_folder(dir);
  capz::CompressOptions o;
  o.lossless = true;
  const size_t lossless = capz::compress(t, o).size();
  o.attr_error = {{"intensity", 0.05}, {"normal", 0.01}};
  const std::vector<uint8_t> z = capz::compress(t, o);
  EXPECT_LT(z.size(), lossless);
  capz::Take back = capz::decompress(z.data(), z.size(), "test");
  const capz::StreamInfo si = capz::describe(z.data(), z.size(), "test");
  ASSERT_EQ(si.pcd_field_bounds.size(), si.pcd_fields.size());
  EXPECT_EQ(si.pcd_field_bounds[4], 0.05);              // intensity
  EXPECT_EQ(si.pcd_field_bounds[5], 0.01);              // normal_x
  EXPECT_EQ(si.pcd_field_bounds[7], 0.01);              // normal_z
  EXPECT_EQ(si.pcd_field_bounds[3], 0.0);               // rgb: lossless
  for (size_t a : {size_t{1}, size_t{2}, size_t{4}}) {  // intensity, normal_x, normal_z
    const double b = a == 1 ? 0.05 : 0.01;
    const std::vector<uint8_t>& x = t.attributes[a].data;
    const std::vector<uint8_t>& y = back.attributes[a].data;
    ASSERT_EQ(x.size(), y.size());
    size_t changed = 0;
    for (size_t k = 0; k < x.size(); k += 4) {
      float fx, fy;
      std::memcpy(&fx, &x[k], 4);
      std::memcpy(&fy, &y[k], 4);
      if (std::isnan(fx)) {
        EXPECT_EQ(std::memcmp(&x[k], &y[k], 4), 0);  // NaN stays NaN, bit for bit
      } else {
        EXPECT_LE(std::fabs(static_cast<double>(fx) - static_cast<double>(fy)), b);
        changed += fx != fy;
      }
    }
    // intensity's quantised values code smaller; normal_x is all 0 (on the grid already), and
    // normal_z's quantised values code no smaller, so they stay exact (test_attr_bound_size.cpp).
    if (a == 1) {
      EXPECT_GT(changed, 0u) << t.attributes[a].name;
    }
  }
  for (size_t a : {size_t{0}, size_t{5}, size_t{6}, size_t{7}})  // rgb, label, desc, _
    EXPECT_EQ(back.attributes[a].data, t.attributes[a].data) << t.attributes[a].name;
  // The promise verify checks: within the bounds, and a field pushed past one is a breach.
  const capz::Promise p = capz::promise_of(si);
  EXPECT_TRUE(capz::check_promise(t, back, p).holds) << capz::check_promise(t, back, p).why;
  float v;
  std::memcpy(&v, &back.attributes[1].data[0], 4);
  v += 0.2f;
  std::memcpy(&back.attributes[1].data[0], &v, 4);
  EXPECT_FALSE(capz::check_promise(t, back, p).holds);
  // Bounds that name nothing, an integer field, or are not positive are refused.
  for (const auto& bad : std::vector<std::map<std::string, double>>{
           {{"colour", 0.1}}, {{"label", 1.0}}, {{"intensity", -1.0}}}) {
    o.attr_error = bad;
    EXPECT_EQ(capz_test::error_of([&] { capz::compress(t, o); }), ErrorCode::kInvalidParameter);
  }
}
