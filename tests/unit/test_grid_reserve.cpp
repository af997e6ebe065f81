// The grid keeps part of the bound in reserve for the float32 rounding of the file the decoder
// writes (grid_choice.cpp, output_rounding_reserve): for C3D and for PCD frames whose x y z are
// float32, which take.h says a PCD take without a layout has (PCDExtra::fields empty: x y z F4,
// and a PCD take without PCD extras). PCD frames of float64 x y z and TRC files keep every
// decoded double: no reserve, a coarser grid.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "capz/codec.h"
#include "capz/stream.h"
#include "codec/grid_choice.h"

namespace capz {
namespace {

// The grid step bounded_grid picks for bound 1e-4 on points near 1000 (float32 spacing there is
// 2^-14 = 6.1e-5, so the reserve of half a spacing takes 3.05e-5 off the bound), for a take of
// format f whose PCD extras are `pcd` (null: none).
double step_for(Format f, std::shared_ptr<PCDExtra> pcd) {
  Take t;
  t.source = "t";
  t.format = f;
  t.units = "m";
  t.pcd = std::move(pcd);
  CompressOptions o;
  o.max_error = 1e-4;
  TakeScan s = start_scan(t, o);
  s.ray_track = false;
  FrameBlock b;
  b.frames = 2;
  b.points = 3;
  for (size_t i = 0; i < 18; ++i) b.xyz.push_back(1000.0 - 0.37 * static_cast<double>(i));
  b.valid.assign(6, 1);
  scan_block(b, t.source, false, 0, &s);
  const Grid g = bounded_grid(t, s, o.max_error);
  EXPECT_EQ(g.mode, PosMode::kGrid);
  EXPECT_GT(g.step, 0.0);
  return g.step;
}

std::shared_ptr<PCDExtra> layout(int xyz_size) {
  auto x = std::make_shared<PCDExtra>();
  for (const char* axis : {"x", "y", "z"}) x->fields.push_back(PCDField{axis, 'F', xyz_size, 1});
  x->fields.push_back(PCDField{"intensity", 'F', 4, 1});
  return x;
}

TEST(GridReserve, GivenPcdFramesWithoutALayoutThenTheFloat32ReserveAsForF4) {
  const double f4 = step_for(Format::kPCDFolder, layout(4));
  const double f8 = step_for(Format::kPCDFolder, layout(8));
  const double trc = step_for(Format::kTRC, nullptr);
  EXPECT_LT(f4, f8) << "float32 x y z keep a reserve: a finer grid";
  EXPECT_EQ(f8, trc) << "float64 x y z are written as decoded: no reserve";
  // No layout: an empty field list, and no PCD extras at all, are x y z F4 (take.h).
  EXPECT_EQ(step_for(Format::kPCDFolder, std::make_shared<PCDExtra>()), f4);
  EXPECT_EQ(step_for(Format::kPCDFolder, nullptr), f4);
  // The reserve is what makes the bound hold after float32 rounding at these magnitudes: half
  // the grid step plus half a float32 spacing (2^-15) stays within 1e-4.
  EXPECT_LE(f4 / 2 + 0x1p-15, 1e-4);
  EXPECT_GT(f8 / 2 + 0x1p-15, 1e-4);
}

}  // namespace
}  // namespace capz
