// Units however a writer spelled them: units_to_metres for one name, c3d::point_units for a whole
// POINT:UNITS parameter (arrays, padding, capitals, entries that disagree), and the C3D writer
// keeping such a parameter as it was.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "capz/io.h"
#include "capz/take.h"
#include "io/c3d_internal.h"

using namespace capz;

namespace {

// POINT:UNITS as a 2-D char array: each entry padded with blanks to `len`.
C3DExtra units_array(const std::vector<std::string>& entries, int len) {
  C3DParameter p;
  p.name = "UNITS";
  p.type = -1;
  p.dims = {len, static_cast<int>(entries.size())};
  for (const std::string& e : entries) {
    std::string padded = e + std::string(static_cast<size_t>(len) - e.size(), ' ');
    p.data.insert(p.data.end(), padded.begin(), padded.end());
  }
  C3DGroup g;
  g.id = 1;
  g.name = "POINT";
  g.params.push_back(p);
  C3DExtra x;
  x.groups.push_back(g);
  return x;
}

C3DExtra units_string(const std::string& s) {
  C3DExtra x = units_array({s}, static_cast<int>(s.size()));
  x.groups[0].params[0].dims = {static_cast<int>(s.size())};
  return x;
}

}  // namespace

TEST(Units, AbbreviationsInAnyCaseAndPadding) {
  EXPECT_DOUBLE_EQ(units_to_metres("mm"), 0.001);
  EXPECT_DOUBLE_EQ(units_to_metres("MM"), 0.001);
  EXPECT_DOUBLE_EQ(units_to_metres("  Mm \t"), 0.001);
  EXPECT_DOUBLE_EQ(units_to_metres("cm"), 0.01);
  EXPECT_DOUBLE_EQ(units_to_metres("CM"), 0.01);
  EXPECT_DOUBLE_EQ(units_to_metres("m"), 1.0);
  EXPECT_DOUBLE_EQ(units_to_metres("M"), 1.0);
  EXPECT_DOUBLE_EQ(units_to_metres("in"), 0.0254);
  EXPECT_DOUBLE_EQ(units_to_metres("ft"), 0.3048);
  EXPECT_DOUBLE_EQ(units_to_metres("um"), 1e-6);
}

TEST(Units, NamesSpelledOutInBothSpellingsSingularOrPlural) {
  for (const char* s : {"meters", "metres", "meter", "metre", "METERS", "Metre"})
    EXPECT_DOUBLE_EQ(units_to_metres(s), 1.0) << s;
  for (const char* s : {"millimetres", "millimeters", "millimetre", "millimeter", "MILLIMETERS"})
    EXPECT_DOUBLE_EQ(units_to_metres(s), 0.001) << s;
  for (const char* s : {"centimeters", "centimetres", "centimetre"})
    EXPECT_DOUBLE_EQ(units_to_metres(s), 0.01) << s;
  EXPECT_DOUBLE_EQ(units_to_metres("inch"), 0.0254);
  EXPECT_DOUBLE_EQ(units_to_metres("inches"), 0.0254);
  EXPECT_DOUBLE_EQ(units_to_metres("feet"), 0.3048);
  EXPECT_DOUBLE_EQ(units_to_metres("foot"), 0.3048);
}

TEST(Units, NamesCutShortToFourLettersOrMore) {
  EXPECT_DOUBLE_EQ(units_to_metres("mete"), 1.0);  // FP1.C3D / FP2.C3D (c3d.org sample 15)
  EXPECT_DOUBLE_EQ(units_to_metres("METE"), 1.0);
  EXPECT_DOUBLE_EQ(units_to_metres("metr"), 1.0);
  EXPECT_DOUBLE_EQ(units_to_metres("mill"), 0.001);
  EXPECT_DOUBLE_EQ(units_to_metres("millim"), 0.001);
  EXPECT_DOUBLE_EQ(units_to_metres("cent"), 0.01);
  EXPECT_DOUBLE_EQ(units_to_metres("centim"), 0.01);
}

TEST(Units, UnknownOrAmbiguousIsZero) {
  for (const char* s : {"", "  ", "furlong", "met", "me", "mi", "metres2", "mm mm", "px", "mmm"})
    EXPECT_EQ(units_to_metres(s), 0.0) << "'" << s << "'";
}

TEST(C3DUnits, ArrayOfPaddedEntriesGivesTheFirst) {
  std::string why = "x";
  EXPECT_EQ(c3d::point_units(units_array({"mm", "mm", "mm"}, 4), &why), "mm");
  EXPECT_EQ(why, "");
  EXPECT_EQ(c3d::point_units(units_array({"", "MM", "mm", "millimetres"}, 12), &why), "MM");
  EXPECT_EQ(why, "");
  // One string holding a unit per point, and blank / NUL padding around a single unit.
  EXPECT_EQ(c3d::point_units(units_string("mm  mm  mm  ")), "mm");
  EXPECT_EQ(c3d::point_units(units_string("  mete")), "mete");
  EXPECT_EQ(c3d::point_units(units_string(std::string("cm\0\0", 4))), "cm");
}

TEST(C3DUnits, EntriesThatDisagreeAreNamedAndNoUnit) {
  std::string why;
  const std::string u = c3d::point_units(units_array({"mm", "mm", "m", "MM", "furlong"}, 8), &why);
  EXPECT_EQ(units_to_metres(u), 0.0) << u;
  EXPECT_NE(why.find("'mm'"), std::string::npos) << why;
  EXPECT_NE(why.find("'m'"), std::string::npos) << why;
  EXPECT_NE(why.find("'furlong'"), std::string::npos) << why;
  EXPECT_EQ(why.find("'MM'"), std::string::npos) << why;  // the same unit as 'mm'
  EXPECT_NE(why.find("--units"), std::string::npos) << why;
}

TEST(C3DUnits, AbsentEmptyOrNotCharIsUnknown) {
  EXPECT_EQ(c3d::point_units(C3DExtra()), "");
  EXPECT_EQ(c3d::point_units(units_string("    ")), "");
  C3DExtra x = units_string("mm");
  x.groups[0].params[0].type = 1;
  EXPECT_EQ(c3d::point_units(x), "");
}

// A take read from a C3D whose POINT:UNITS is an array written back: the reader's units and the
// parameter's bytes are what they were.
TEST(C3DUnits, ReaderUsesTheResolvedUnitAndTheWriterKeepsTheParameter) {
  Take t;
  t.format = Format::kC3D;
  t.resize(2, 1);
  t.rate = 100;
  t.valid = {1, 1};
  t.xyz = {1, 2, 3, 4, 5, 6};
  t.labels = {"A"};
  t.c3d = std::make_shared<C3DExtra>(units_array({"MM", "mm", ""}, 4));
  t.c3d->float_storage = true;
  t.units = c3d::point_units(*t.c3d);
  ASSERT_EQ(t.units, "MM");
  const auto bytes = c3d::encode_c3d_file(t, {}, "units.c3d");
  const Take back = read_c3d_bytes(bytes.data(), bytes.size(), "units.c3d");
  EXPECT_EQ(back.units, "MM");
  const C3DParameter* p = back.c3d->param("POINT", "UNITS");
  ASSERT_NE(p, nullptr);
  EXPECT_EQ(p->dims, (std::vector<int>{4, 3}));
  EXPECT_EQ(p->data, t.c3d->groups[0].params[0].data);
  // Units set otherwise replace the parameter.
  t.units = "m";
  const auto changed = c3d::encode_c3d_file(t, {}, "units.c3d");
  EXPECT_EQ(read_c3d_bytes(changed.data(), changed.size(), "units.c3d").units, "m");
}

TEST(C3DUnits, ReaderWarnsWhenEntriesDisagree) {
  Take t;
  t.format = Format::kC3D;
  t.resize(1, 1);
  t.valid = {1};
  t.xyz = {1, 2, 3};
  t.c3d = std::make_shared<C3DExtra>(units_array({"mm", "cm"}, 2));
  t.c3d->float_storage = true;
  t.units = c3d::point_units(*t.c3d);
  const auto bytes = c3d::encode_c3d_file(t, {}, "mixed.c3d");
  const Take back = read_c3d_bytes(bytes.data(), bytes.size(), "mixed.c3d");
  EXPECT_EQ(units_to_metres(back.units), 0.0);
  bool named = false;
  for (const auto& w : back.warnings) named = named || w.find("'cm'") != std::string::npos;
  EXPECT_TRUE(named);
}
