// C3D writer, parameter codec and EVENT group on hand-built byte arrays (c3d_builder.h).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>

#include "c3d_builder.h"
#include "capz/error.h"
#include "capz/io.h"
#include "coding/c3d_params.h"
#include "core/atomic_file.h"
#include "io/c3d_internal.h"
#include "support/c3d_compare.h"
#include "test_util.h"

using namespace capz;
using capz::testing_support::expect_same_groups;
using capz::testing_support::expect_same_take;
namespace fs = std::filesystem;
using namespace c3d_builder;

// ---- writing --------------------------------------------------------------------------------

TEST(C3DWrite, ReadWriteReadIsExactForEveryEncoding) {
  for (int proc : {c3d::kIntel, c3d::kDec, c3d::kMips})
    for (bool fl : {false, true}) {
      SCOPED_TRACE("processor " + std::to_string(proc) + (fl ? " float" : " int16"));
      Take t = read(small_trial(proc, fl));
      auto bytes = c3d::encode_c3d_file(t, {}, "rt.c3d");
      EXPECT_EQ(bytes[512 + 3], c3d::kIntel);
      Take back = read_c3d_bytes(bytes.data(), bytes.size(), "rt.c3d");
      expect_same_take(t, back);
      EXPECT_EQ(back.c3d->float_storage, fl);
      EXPECT_TRUE(back.warnings.empty());
      // Every parameter kept, in order, with its description and lock; only DATA_START moves.
      expect_same_groups(t.c3d->groups, back.c3d->groups, {"POINT:DATA_START"});
      // A second generation is byte-identical.
      EXPECT_EQ(c3d::encode_c3d_file(back, {}, "rt2.c3d"), bytes);
    }
}

// Some writers store counts as one byte (sample_35's Mega Electronics file: POINT:DATA_START).
// The writer updates such a parameter in place: still one byte while the value fits one.
TEST(C3DWrite, ByteTypedCountsStayOneByte) {
  Built b = small_trial(c3d::kIntel, false);
  for (Param& p : b.groups[0].params)
    if (p.name == "DATA_START" || p.name == "USED") p.type = 1;
  Take t = read(b);
  ASSERT_EQ(t.c3d->param("POINT", "DATA_START")->type, 1);
  auto bytes = c3d::encode_c3d_file(t, {}, "byte.c3d");
  Take back = read_c3d_bytes(bytes.data(), bytes.size(), "byte.c3d");
  for (const char* name : {"DATA_START", "USED"}) {
    SCOPED_TRACE(name);
    const C3DParameter* p = back.c3d->param("POINT", name);
    ASSERT_NE(p, nullptr);
    EXPECT_EQ(p->type, 1);
    EXPECT_EQ(p->data.size(), 1u);
  }
  EXPECT_EQ(back.c3d->param("POINT", "USED")->as_ints()[0], 3);
  const int header_data_start = bytes[16] | bytes[17] << 8;  // header word 9
  EXPECT_EQ(back.c3d->param("POINT", "DATA_START")->as_ints()[0], header_data_start);
  expect_same_take(t, back);
}

TEST(C3DWrite, Int16StorageKeepsTheStoredIntegers) {
  Built b = small_trial(c3d::kIntel, false);
  b.scale = 0.0833333;  // not exact in binary
  b.groups.clear();
  standard_groups(b, {"A", "B", "C"});
  Take t = read(b);
  auto bytes = c3d::encode_c3d_file(t, {}, "q.c3d");
  Take back = read_c3d_bytes(bytes.data(), bytes.size(), "q.c3d");
  EXPECT_FALSE(back.c3d->float_storage);
  EXPECT_EQ(0, std::memcmp(t.xyz.data(), back.xyz.data(), t.xyz.size() * 8));
  // The data section of the written file holds the same integers as the source.
  auto src = b.bytes();
  size_t src_data = (static_cast<size_t>(src[16] | (src[17] << 8)) - 1) * 512;
  size_t out_data = (static_cast<size_t>(bytes[16] | (bytes[17] << 8)) - 1) * 512;
  ASSERT_EQ(src.size() - src_data, bytes.size() - out_data);
  EXPECT_TRUE(std::equal(src.begin() + static_cast<long>(src_data), src.end(),
                         bytes.begin() + static_cast<long>(out_data)));

  // c3d_float writes float; values stay within float precision of the int16 grid.
  WriteOptions o;
  o.c3d_float = true;
  auto fb = c3d::encode_c3d_file(t, o, "f.c3d");
  Take ft = read_c3d_bytes(fb.data(), fb.size(), "f.c3d");
  EXPECT_TRUE(ft.c3d->float_storage);
  for (size_t i = 0; i < t.xyz.size(); ++i) EXPECT_NEAR(ft.xyz[i], t.xyz[i], 1e-3);
}

TEST(C3DWrite, TakeFromElsewhereGetsAFreshParameterSection) {
  Take t;
  t.format = Format::kTRC;
  t.resize(5, 2);
  t.rate = 60;
  t.units = "m";
  t.first_frame = 10;
  t.labels = {"head", "toe"};
  for (size_t f = 0; f < 5; ++f)
    for (size_t p = 0; p < 2; ++p) {
      if (f == 3 && p == 0) continue;
      double* x = t.at(f, p);
      x[0] = 0.5 + 0.001 * static_cast<double>(f);
      x[1] = static_cast<float>(1.25 * static_cast<double>(p));
      x[2] = -0.75;
      t.valid[f * 2 + p] = 1;
    }
  for (auto& v : t.xyz) v = static_cast<float>(v);  // exact in float storage
  auto bytes = c3d::encode_c3d_file(t, {}, "fresh.c3d");
  Take back = read_c3d_bytes(bytes.data(), bytes.size(), "fresh.c3d");
  EXPECT_TRUE(back.warnings.empty()) << back.warnings[0];
  EXPECT_TRUE(back.c3d->float_storage);
  EXPECT_EQ(back.valid, t.valid);
  EXPECT_EQ(back.xyz, t.xyz);
  EXPECT_EQ(back.labels, t.labels);
  EXPECT_EQ(back.units, "m");
  EXPECT_DOUBLE_EQ(back.rate, 60);
  EXPECT_EQ(back.first_frame, 10);
  for (const char* g : {"POINT", "ANALOG", "TRIAL"}) EXPECT_NE(back.c3d->group(g), nullptr) << g;
  EXPECT_NE(back.c3d->param("POINT", "SCALE"), nullptr);
  EXPECT_LT(back.c3d->param("POINT", "SCALE")->as_floats()[0], 0);
}

// new_c3d_parameters gives the section write_c3d writes for a take alone: setting it as the
// take's section changes no byte, and a group added to it is written beside it.
TEST(C3DWrite, NewParameterSectionIsWhatTheWriterGivesATakeAlone) {
  for (int with_analog = 0; with_analog < 2; ++with_analog) {
    Take t;
    t.resize(7, 3);
    t.rate = 120;
    t.units = "mm";
    t.first_frame = 4;
    t.labels = {"A", "B", "C"};
    for (size_t i = 0; i < t.valid.size(); ++i) {
      t.valid[i] = i % 5 != 2;
      for (int a = 0; a < 3; ++a)
        t.xyz[3 * i + a] = t.valid[i] ? 1000.5 - 37.25 * static_cast<double>(i + a) : 0;
    }
    if (with_analog) {
      t.analog.channels = 2;
      t.analog.samples_per_frame = 4;
      t.analog.rate = 480;
      t.analog.labels = {"Fz", "EMG"};
      t.analog.values.resize(7 * 4 * 2);
      for (size_t i = 0; i < t.analog.values.size(); ++i)
        t.analog.values[i] = 0.5 * static_cast<double>(i) - 3;
    }
    const auto alone = c3d::encode_c3d_file(t, {}, "alone.c3d");
    Take s = t;
    s.c3d = new_c3d_parameters(t, "s.c3d");
    EXPECT_TRUE(s.c3d->float_storage);
    EXPECT_EQ(s.c3d->point_scale, 0);
    EXPECT_EQ(c3d::encode_c3d_file(s, {}, "s.c3d"), alone) << with_analog;

    C3DGroup g;
    g.id = 9;
    g.name = "SUBJECTS";
    C3DParameter w;
    w.name = "WEIGHT";
    w.description = "kg";
    w.type = 4;
    w.data = {0, 0, 0x8c, 0x42};  // 70.0f
    g.params.push_back(w);
    s.c3d->groups.push_back(g);
    const auto with = c3d::encode_c3d_file(s, {}, "s.c3d");
    Take back = read_c3d_bytes(with.data(), with.size(), "s.c3d");
    ASSERT_NE(back.c3d->param("SUBJECTS", "WEIGHT"), nullptr);
    EXPECT_EQ(back.c3d->param("SUBJECTS", "WEIGHT")->as_floats(), std::vector<float>{70.0f});
    EXPECT_EQ(back.xyz, read_c3d_bytes(alone.data(), alone.size(), "a").xyz);
    EXPECT_EQ(back.analog.values, t.analog.values);
    EXPECT_EQ(back.first_frame, 4);
  }
  Take big;
  big.resize(1, 70000);
  EXPECT_THROW(new_c3d_parameters(big, "big"), Error);
}

TEST(C3DWrite, WritesAtomicallyAndRefusesToOverwrite) {
  capz_test::TempDir tmp("capz_c3d_unit");
  const std::string dir = tmp.path().string();
  std::string out = tmp.file("walk.c3d");
  Take t = read(small_trial(c3d::kDec, true));
  write_c3d(t, out);
  Take back = read_c3d(out);
  expect_same_take(t, back);
  try {
    write_c3d(t, out);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kUsage);
  }
  WriteOptions o;
  o.overwrite = true;
  write_c3d(t, out, o);
  size_t entries = 0;
  for (const auto& e : fs::directory_iterator(dir)) (void)e, ++entries;
  EXPECT_EQ(entries, 1u);  // no temporary left behind
}

// ---- parameter codec ------------------------------------------------------------------------

TEST(C3DParams, EncodeDecodeIsExact) {
  Built b = small_trial(c3d::kMips, true);
  b.groups[0].params.push_back({"BYTES", 1, {3}, {1, 200, 255}, "", "raw bytes", true});
  b.groups[0].params.push_back({"MATRIX", 4, {2, 3}, {1, 2, 3, 4.5, -5, 1e-8}, "", "", false});
  b.groups[0].params.push_back({"EMPTY", -1, {0, 0}, {}, "", "", false});
  b.groups.push_back({9, "CUSTOM", "locked group", {}});
  Take t = read(b);
  C3DExtra x = *t.c3d;
  C3DGroup implicit;
  implicit.id = 12;
  implicit.implicit = true;
  implicit.params.push_back(x.groups[0].params[0]);
  x.groups.push_back(implicit);
  x.groups[2].locked = true;

  std::vector<uint8_t> enc = encode_c3d_parameters(x);
  ASSERT_EQ(enc.size() % 512, 0u);
  EXPECT_EQ(enc[3], 84);
  EXPECT_EQ(enc[2], enc.size() / 512);
  C3DExtra y;
  decode_c3d_parameters(enc.data(), enc.size(), "params", &y);
  expect_same_groups(x.groups, y.groups);
  EXPECT_EQ(encode_c3d_parameters(y), enc);
  EXPECT_EQ(y.param("POINT", "MATRIX")->as_floats()[3], 4.5f);
  EXPECT_EQ(y.param("POINT", "BYTES")->as_ints()[1], 200);

  // A cut section is an error for the container, never a silent loss.
  for (size_t cut : {size_t{3}, size_t{40}, size_t{300}}) {
    try {
      decode_c3d_parameters(enc.data(), cut, "params", &y);
      ADD_FAILURE() << cut;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
      EXPECT_NE(std::string(e.what()).find("params"), std::string::npos);
    }
  }
}

TEST(C3DParams, EncoderRejectsWhatC3DCannotHold) {
  C3DExtra x;
  C3DGroup g;
  g.id = 1;
  g.name = "POINT";
  C3DParameter p;
  p.name = "BAD";
  p.type = 2;
  p.dims = {3};
  p.data = {1, 2};  // 2 bytes for 3 int16
  g.params.push_back(p);
  x.groups.push_back(g);
  EXPECT_THROW(encode_c3d_parameters(x), Error);
  x.groups[0].params[0].dims = {1};
  x.groups[0].name = std::string(200, 'A');
  EXPECT_THROW(encode_c3d_parameters(x), Error);
}

// ---- EVENT group ------------------------------------------------------------------------------

namespace {
C3DParameter float_array(const std::string& name, std::vector<int> dims, std::vector<float> v) {
  C3DParameter p;
  p.name = name;
  p.type = 4;
  p.dims = std::move(dims);
  p.data.resize(4 * v.size());
  for (size_t i = 0; i < v.size(); ++i) std::memcpy(&p.data[4 * i], &v[i], 4);
  return p;
}
}  // namespace

TEST(C3DEvents, FieldsFromTheEventGroupWhereGiven) {
  C3DExtra x;
  EXPECT_TRUE(c3d_events(x).empty());
  C3DGroup& g = c3d::ensure_group(x.groups, "EVENT", "");
  EXPECT_TRUE(c3d_events(x).empty());  // no TIMES: no event
  c3d::set_int16(c3d::ensure_param(g, "USED", ""), 3);
  g.params.push_back(float_array("TIMES", {2, 3}, {0, 1.5f, 2, 0.25f, 0, 7}));
  c3d::set_strings(c3d::ensure_param(g, "LABELS", ""), {"Foot Strike", "Foot Off", "Event"});
  c3d::set_strings(c3d::ensure_param(g, "CONTEXTS", ""), {"Left", "Right"});  // one short
  c3d::set_int16_array(c3d::ensure_param(g, "ICON_IDS", ""), {1, 2, 0});
  std::vector<C3DEvent> e = c3d_events(x);
  ASSERT_EQ(e.size(), 3u);
  EXPECT_EQ(e[0].label, "Foot Strike");
  EXPECT_EQ(e[0].context, "Left");
  EXPECT_DOUBLE_EQ(e[0].time, 1.5);
  EXPECT_DOUBLE_EQ(e[1].time, 120.25);  // 2 minutes and 0.25 s
  EXPECT_EQ(e[1].icon_id, 2);
  EXPECT_EQ(e[2].context, "");
  EXPECT_EQ(e[2].generic_flag, 0);  // GENERIC_FLAGS absent
  EXPECT_EQ(e[2].description, "");
  EXPECT_DOUBLE_EQ(e[2].time, 7);

  c3d::set_int16(*c3d::find_param(g, "USED"), 2);  // USED counts
  EXPECT_EQ(c3d_events(x).size(), 2u);
  c3d::set_int16(*c3d::find_param(g, "USED"), 9);  // never more than TIMES holds
  EXPECT_EQ(c3d_events(x).size(), 3u);
  C3DParameter& used = *c3d::find_param(g, "USED");  // a byte USED counts too
  used.type = 1;
  used.dims.clear();
  used.data = {1};
  EXPECT_EQ(c3d_events(x).size(), 1u);
  g.params.erase(g.params.begin());  // without USED, as many as TIMES holds
  EXPECT_EQ(c3d_events(x).size(), 3u);
  *c3d::find_param(g, "TIMES") = float_array("TIMES", {5}, {0, 1, 0, 2, 9});  // 1-D, odd
  e = c3d_events(x);
  ASSERT_EQ(e.size(), 2u);
  EXPECT_DOUBLE_EQ(e[1].time, 2);
}

TEST(C3DEvents, SetThenReadGivesThemBackAndSurvivesTheWriter) {
  std::vector<C3DEvent> ev(3);
  ev[0].label = "Foot Strike";
  ev[0].context = "Left";
  ev[0].time = 1.25;
  ev[0].icon_id = 1;
  ev[1].label = "Foot Off";
  ev[1].context = "Right";
  ev[1].description = "toe off";
  ev[1].subject = "S1";
  ev[1].time = 125.5;  // written as 2 minutes and 5.5 s
  ev[1].generic_flag = -3;
  ev[2].time = 0;

  Take t;
  t.resize(4, 1);
  t.rate = 100;
  t.units = "mm";
  for (size_t i = 0; i < 3; ++i) t.xyz[i] = 10.0 + static_cast<double>(i);
  t.valid[0] = 1;
  t.c3d = new_c3d_parameters(t, "ev.c3d");
  set_c3d_events(t.c3d.get(), ev);
  const C3DParameter* times = t.c3d->param("EVENT", "TIMES");
  ASSERT_NE(times, nullptr);
  EXPECT_EQ(times->dims, (std::vector<int>{2, 3}));
  EXPECT_EQ(times->as_floats()[2], 2.0f);
  EXPECT_EQ(times->as_floats()[3], 5.5f);
  auto same = [&](const std::vector<C3DEvent>& got) {
    ASSERT_EQ(got.size(), ev.size());
    for (size_t i = 0; i < ev.size(); ++i) {
      EXPECT_EQ(got[i].label, ev[i].label) << i;
      EXPECT_EQ(got[i].context, ev[i].context) << i;
      EXPECT_EQ(got[i].description, ev[i].description) << i;
      EXPECT_EQ(got[i].subject, ev[i].subject) << i;
      EXPECT_DOUBLE_EQ(got[i].time, ev[i].time) << i;
      EXPECT_EQ(got[i].icon_id, ev[i].icon_id) << i;
      EXPECT_EQ(got[i].generic_flag, ev[i].generic_flag) << i;
    }
  };
  same(c3d_events(*t.c3d));
  const auto bytes = c3d::encode_c3d_file(t, {}, "ev.c3d");
  same(c3d_events(*read_c3d_bytes(bytes.data(), bytes.size(), "ev.c3d").c3d));

  // Replacing: one event left in every list; refusals change nothing.
  ev.resize(1);
  set_c3d_events(t.c3d.get(), ev);
  same(c3d_events(*t.c3d));
  EXPECT_EQ(t.c3d->param("EVENT", "LABELS")->as_strings().size(), 1u);
  const std::vector<C3DGroup> before = t.c3d->groups;
  std::vector<C3DEvent> bad = ev;
  bad[0].time = -1;
  EXPECT_THROW(set_c3d_events(t.c3d.get(), bad), Error);
  bad[0].time = 1;
  bad[0].icon_id = 40000;
  EXPECT_THROW(set_c3d_events(t.c3d.get(), bad), Error);
  EXPECT_THROW(set_c3d_events(t.c3d.get(), std::vector<C3DEvent>(256)), Error);
  expect_same_groups(t.c3d->groups, before);
}
