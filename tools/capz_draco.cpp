// Draco's point-cloud coder as a peer for PCD sequences with fields (issue 15), in-process
// through libdraco, one draco::PointCloud per frame:
//
//   capz_draco DIR --max-error B [--floats raw|bits] [--speed S]
//
// DIR is a PCD folder (anything capz reads). Per frame, the points with finite x y z become a
// PointCloud: Draco has no NaN points and no organized layout (width x height), so the NaN
// points and the layout are dropped (counted in the output). Every other field becomes one
// attribute, its values unchanged:
//   rgb / rgba (4 bytes, PCL's packed colour)  COLOR uint8 x 4 (r g b a: alpha kept too);
//   normal_x normal_y normal_z (float32)       NORMAL float32 x 3;
//   any other field                            GENERIC, its PCD type and COUNT (8-byte fields
//                                              as two 32-bit components).
// Positions are quantised (Draco's only position coding): per frame the fewest bits whose
// grid (the largest bounding-box extent / (2^bits - 1)) keeps every coordinate within B, and
// more if the decoded frame says otherwise. Integer attributes are never quantised (Draco codes
// them losslessly: prediction + rANS). Float attributes with quantisation 0: Draco stores them
// raw (its generic sequential attribute coder: 4 bytes a value, no entropy coding), losslessly,
// and then cannot use its kd-tree coder, only the sequential one (point order kept).
// --floats bits gives Draco the float fields' bit patterns as uint32 attributes instead
// (lossless, entropy-coded, and the kd-tree coder becomes possible: points reordered).
//
// Every frame is decoded and measured: with the sequential coder point i comes back as point i;
// the kd-tree coder reorders points, so each original point is paired with its nearest decoded
// point (per-coordinate distance, tools/cloud_match.h: a lower bound of the true error) and
// attributes are compared on that pairing (with the closest of the decoded points at exactly
// that distance, which a coarse grid makes coincide), and also as a multiset per frame (sorted
// rows of attribute bytes), which shows whether they came back exactly. Prints JSON.
#include <draco/compression/decode.h>
#include <draco/compression/expert_encode.h>
#include <draco/point_cloud/point_cloud.h>
#include <draco/point_cloud/point_cloud_builder.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

#include "capz/error.h"
#include "capz/io.h"
#include "capz/take.h"
#include "cloud_match.h"
#include "raw_io.h"

namespace {

// One Draco attribute made of one or more PCD fields, with its rows of bytes per point.
struct Group {
  std::string name;   // "rgb", "normal", or the field's name
  std::string draco;  // how Draco holds it, for the report
  draco::GeometryAttribute::Type type = draco::GeometryAttribute::GENERIC;
  draco::DataType dtype = draco::DT_UINT8;
  int components = 1;
  std::vector<size_t> fields;  // indices in Take::attributes
  char elem_type = 'U';        // how a row's elements read: PCD type and size
  int elem_size = 1;
  bool rgb = false;  // bytes b g r a stored as r g b a
  size_t row_bytes = 0;
  // Results over all frames.
  size_t exact_points = 0, points = 0;
  double max_abs = 0;
  bool multiset_exact = true;
};

draco::DataType int_type(char t, int size) {
  if (t == 'I') return size == 1 ? draco::DT_INT8 : size == 2 ? draco::DT_INT16 : draco::DT_INT32;
  return size == 1 ? draco::DT_UINT8 : size == 2 ? draco::DT_UINT16 : draco::DT_UINT32;
}

std::vector<Group> plan(const capz::Take& t, bool float_bits) {
  std::vector<Group> g;
  const auto& at = t.attributes;
  for (size_t i = 0; i < at.size(); ++i) {
    const capz::PointAttribute& a = at[i];
    Group x;
    x.name = a.name;
    x.fields = {i};
    x.elem_type = a.type;
    x.elem_size = a.size;
    x.row_bytes = a.bytes_per_point();
    if (a.name == "_") continue;  // PCD padding: no values
    if ((a.name == "rgb" || a.name == "rgba") && a.size == 4 && a.count == 1) {
      x.type = draco::GeometryAttribute::COLOR;
      x.dtype = draco::DT_UINT8;
      x.components = 4;
      x.elem_type = 'U';
      x.elem_size = 1;
      x.rgb = true;
      x.draco = "COLOR uint8 x4";
    } else if (a.name == "normal_x" && i + 2 < at.size() && at[i + 1].name == "normal_y" &&
               at[i + 2].name == "normal_z" && a.type == 'F' && a.size == 4 && a.count == 1 &&
               at[i + 1].type == 'F' && at[i + 1].size == 4 && at[i + 1].count == 1 &&
               at[i + 2].type == 'F' && at[i + 2].size == 4 && at[i + 2].count == 1) {
      x.name = "normal";
      x.fields = {i, i + 1, i + 2};
      x.components = 3;
      x.row_bytes = 12;
      x.type = float_bits ? draco::GeometryAttribute::GENERIC : draco::GeometryAttribute::NORMAL;
      x.dtype = float_bits ? draco::DT_UINT32 : draco::DT_FLOAT32;
      x.draco = float_bits ? "GENERIC uint32 x3 (float bits)" : "NORMAL float32 x3 (raw)";
      i += 2;
    } else if (a.size == 8) {
      x.components = 2 * a.count;
      x.dtype = a.type == 'I' ? draco::DT_INT32 : draco::DT_UINT32;
      x.draco = "GENERIC 32-bit x" + std::to_string(x.components) + " (8-byte values split)";
    } else if (a.type == 'F') {
      x.components = a.count;
      x.dtype = float_bits ? draco::DT_UINT32 : draco::DT_FLOAT32;
      x.draco = std::string(float_bits ? "GENERIC uint32 (float bits)" : "GENERIC float32 (raw)") +
                " x" + std::to_string(a.count);
    } else {
      x.components = a.count;
      x.dtype = int_type(a.type, a.size);
      x.draco = std::string("GENERIC ") + (a.type == 'I' ? "int" : "uint") +
                std::to_string(8 * a.size) + " x" + std::to_string(a.count);
    }
    if (x.components > 127)
      capz::fail(capz::ErrorCode::kUsage, t.source, "field " + a.name + " has too many values");
    g.push_back(x);
  }
  return g;
}

// The row of group `g` for point p of frame f (Draco's layout).
void row(const capz::Take& t, const Group& g, size_t f, size_t p, uint8_t* out) {
  size_t o = 0;
  for (size_t fi : g.fields) {
    const capz::PointAttribute& a = t.attributes[fi];
    size_t b = a.bytes_per_point();
    std::memcpy(out + o, &a.data[(f * t.points + p) * b], b);
    o += b;
  }
  if (g.rgb) std::swap(out[0], out[2]);  // b g r a -> r g b a
}

double element(const uint8_t* p, char type, int size) {
  if (type == 'F') {
    if (size == 4) {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
    double v;
    std::memcpy(&v, p, 8);
    return v;
  }
  uint64_t u = 0;
  for (int i = 0; i < size; ++i) u |= static_cast<uint64_t>(p[i]) << (8 * i);
  if (type == 'I' && size < 8 && (u >> (8 * size - 1)) != 0) u |= ~uint64_t{0} << (8 * size);
  return type == 'I' ? static_cast<double>(static_cast<int64_t>(u)) : static_cast<double>(u);
}

double row_diff(const Group& g, const uint8_t* a, const uint8_t* b) {
  double m = 0;
  for (size_t o = 0; o < g.row_bytes; o += static_cast<size_t>(g.elem_size)) {
    double x = element(a + o, g.elem_type, g.elem_size),
           y = element(b + o, g.elem_type, g.elem_size);
    if (std::isnan(x) && std::isnan(y)) continue;
    double d = std::fabs(x - y);
    m = std::max(m, std::isnan(d) ? INFINITY : d);
  }
  return m;
}

// Draco's header: "DRACO", major, minor, encoder type, encoder method (0 sequential, 1 kd-tree).
int method_of(const draco::EncoderBuffer& b) {
  return b.size() > 8 ? static_cast<unsigned char>(b.data()[8]) : -1;
}

struct Totals {
  size_t bytes = 0, kept = 0, frames = 0, kd_frames = 0;
  int min_bits = 99, max_bits = 0;
  double pos_max = 0, pos_max_euclid = 0, enc_s = 0, dec_s = 0;
};

// The points of frame f with a valid, finite x y z.
std::vector<size_t> finite_points(const capz::Take& t, size_t f) {
  std::vector<size_t> idx;
  for (size_t p = 0; p < t.points; ++p) {
    const double* x = t.at(f, p);
    if (t.is_valid(f, p) && std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]))
      idx.push_back(p);
  }
  return idx;
}

// The float32 positions of frame f's points idx into *pos; returns the largest extent of their
// bounding box.
double frame_positions(const capz::Take& t, size_t f, const std::vector<size_t>& idx,
                       std::vector<float>* pos) {
  const size_t n = idx.size();
  pos->assign(n * 3, 0.0f);
  float lo[3], hi[3];
  for (int a = 0; a < 3; ++a) lo[a] = hi[a] = static_cast<float>(t.at(f, idx[0])[a]);
  for (size_t i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) {
      (*pos)[i * 3 + a] = static_cast<float>(t.at(f, idx[i])[a]);
      lo[a] = std::min(lo[a], (*pos)[i * 3 + a]);
      hi[a] = std::max(hi[a], (*pos)[i * 3 + a]);
    }
  double range = 0;
  for (int a = 0; a < 3; ++a) range = std::max(range, static_cast<double>(hi[a]) - lo[a]);
  return range;
}

// A frame as a Draco point cloud, with each group's attribute id and rows (Draco's layout).
struct FrameCloud {
  std::unique_ptr<draco::PointCloud> pc;
  int pos_id = -1;
  std::vector<int> ids;
  std::vector<std::vector<uint8_t>> rows;
};

// Builds frame f's cloud of the points idx at positions pos, one attribute a group.
FrameCloud build_cloud(const capz::Take& t, size_t f, const std::vector<size_t>& idx,
                       const std::vector<float>& pos, const std::vector<Group>& groups) {
  const size_t n = idx.size();
  FrameCloud c;
  c.rows.resize(groups.size());
  draco::PointCloudBuilder b;
  b.Start(static_cast<draco::PointIndex::ValueType>(n));
  c.pos_id = b.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
  b.SetAttributeValuesForAllPoints(c.pos_id, pos.data(), 0);
  for (size_t k = 0; k < groups.size(); ++k) {
    const Group& g = groups[k];
    c.rows[k].resize(n * g.row_bytes);
    for (size_t i = 0; i < n; ++i) row(t, g, f, idx[i], &c.rows[k][i * g.row_bytes]);
    c.ids.push_back(b.AddAttribute(g.type, static_cast<int8_t>(g.components), g.dtype));
    b.SetAttributeValuesForAllPoints(c.ids.back(), c.rows[k].data(), 0);
  }
  c.pc = b.Finalize(false);
  if (!c.pc)
    capz::fail(capz::ErrorCode::kInternal, t.source, "draco refused frame " + std::to_string(f));
  return c;
}

// The fewest position bits (at most 30) whose grid over an extent of `range` keeps every
// coordinate within bound.
int first_bits(double range, double bound) {
  int bits = 1;
  while (bits < 30 && range / (std::pow(2.0, bits) - 1) / 2 > bound) ++bits;
  return bits;
}

// Encodes the cloud with `bits` position bits into *buf and decodes it again; clocks gets the
// clock before encoding, after encoding and after decoding.
std::unique_ptr<draco::PointCloud> code_frame(const FrameCloud& c, int speed, int bits,
                                              const std::string& source, size_t f,
                                              draco::EncoderBuffer* buf, std::clock_t clocks[3]) {
  draco::ExpertEncoder enc(*c.pc);
  enc.SetSpeedOptions(speed, speed);
  enc.SetAttributeQuantization(c.pos_id, bits);
  clocks[0] = std::clock();
  draco::Status st = enc.EncodeToBuffer(buf);
  clocks[1] = std::clock();
  if (!st.ok())
    capz::fail(capz::ErrorCode::kInternal, source,
               "draco encode of frame " + std::to_string(f) + ": " + st.error_msg_string());
  draco::DecoderBuffer db;
  db.Init(buf->data(), buf->size());
  draco::Decoder dec;
  auto r = dec.DecodePointCloudFromBuffer(&db);
  clocks[2] = std::clock();
  if (!r.ok())
    capz::fail(capz::ErrorCode::kInternal, source,
               "draco decode of frame " + std::to_string(f) + ": " + r.status().error_msg_string());
  return std::move(r).value();
}

// The decoded positions, checked: some points, and all n of them in order for the sequential
// coder (kd false).
std::vector<float> decoded_positions(const draco::PointCloud& out, size_t n, bool kd,
                                     const std::string& source, size_t f) {
  const size_t m = out.num_points();
  const draco::PointAttribute* op = out.GetNamedAttribute(draco::GeometryAttribute::POSITION);
  if (op == nullptr || m == 0 || (!kd && m != n))
    capz::fail(capz::ErrorCode::kInternal, source,
               "draco gave back " + std::to_string(m) + " of " + std::to_string(n) +
                   " points in frame " + std::to_string(f));
  std::vector<float> back(m * 3);
  for (size_t i = 0; i < m; ++i)
    op->GetMappedValue(draco::PointIndex(static_cast<uint32_t>(i)), &back[i * 3]);
  return back;
}

// Each original point's decoded point (with the decoded points at the same distance, `ties`, for
// the attributes) and the largest per-coordinate and euclidean errors.
struct Pairing {
  std::vector<size_t> pair;
  std::vector<std::vector<uint32_t>> ties;
  double emax = 0, eeuc = 0;
};

// Pairs the points: identity for the sequential coder, nearest decoded point for the kd-tree one.
Pairing pair_points(const std::vector<float>& pos, const std::vector<float>& back, bool kd,
                    double bound) {
  const size_t n = pos.size() / 3;
  Pairing r;
  r.pair.resize(n);
  r.ties.resize(kd ? n : 0);
  capz_tools::CloudGrid grid(back, bound);
  for (size_t i = 0; i < n; ++i) {
    double e = 0;
    if (kd) {
      long j = grid.nearest(&pos[i * 3], &e, &r.ties[i]);
      r.pair[i] = static_cast<size_t>(j < 0 ? 0 : j);
    } else {
      r.pair[i] = i;
    }
    double s = 0;
    e = 0;
    for (int a = 0; a < 3; ++a) {
      double d = static_cast<double>(back[r.pair[i] * 3 + a]) - pos[i * 3 + a];
      e = std::max(e, std::fabs(d));
      s += d * d;
    }
    r.emax = std::max(r.emax, e);
    r.eeuc = std::max(r.eeuc, std::sqrt(s));
  }
  return r;
}

// Adds a coded frame of n points to the totals.
void add_frame(size_t bytes, size_t n, bool kd, int bits, const Pairing& pr,
               const std::clock_t clocks[3], Totals* tot) {
  tot->bytes += bytes;
  tot->kept += n;
  tot->frames += 1;
  tot->kd_frames += kd ? 1 : 0;
  tot->min_bits = std::min(tot->min_bits, bits);
  tot->max_bits = std::max(tot->max_bits, bits);
  tot->pos_max = std::max(tot->pos_max, pr.emax);
  tot->pos_max_euclid = std::max(tot->pos_max_euclid, pr.eeuc);
  tot->enc_s += static_cast<double>(clocks[1] - clocks[0]) / CLOCKS_PER_SEC;
  tot->dec_s += static_cast<double>(clocks[2] - clocks[1]) / CLOCKS_PER_SEC;
}

// The m decoded rows of group g's attribute oa (checked: present, with g's row size).
std::vector<uint8_t> decoded_rows(const draco::PointAttribute* oa, const Group& g, size_t m,
                                  const std::string& source) {
  if (oa == nullptr || static_cast<size_t>(oa->byte_stride()) != g.row_bytes)
    capz::fail(capz::ErrorCode::kInternal, source, "draco lost attribute " + g.name);
  std::vector<uint8_t> got(m * g.row_bytes);
  for (size_t i = 0; i < m; ++i)
    oa->GetMappedValue(draco::PointIndex(static_cast<uint32_t>(i)), &got[i * g.row_bytes]);
  return got;
}

// Adds to g the comparison of its n original rows with the m decoded ones: point by point on
// the pairing, and as a multiset.
void compare_rows(const std::vector<uint8_t>& rows, const std::vector<uint8_t>& got, size_t n,
                  size_t m, const Pairing& pr, bool kd, Group* g) {
  for (size_t i = 0; i < n; ++i) {
    const uint8_t* x = &rows[i * g->row_bytes];
    // The closest attribute among the decoded points the pairing cannot tell apart.
    bool exact = false;
    double diff = INFINITY;
    auto take = [&](size_t j) {
      const uint8_t* y = &got[j * g->row_bytes];
      exact = exact || std::memcmp(x, y, g->row_bytes) == 0;
      diff = std::min(diff, row_diff(*g, x, y));
    };
    take(pr.pair[i]);
    if (kd)
      for (uint32_t j : pr.ties[i]) take(j);
    g->points += 1;
    g->exact_points += exact ? 1 : 0;
    g->max_abs = std::max(g->max_abs, diff);
  }
  // As a multiset: the sorted rows of both sides.
  auto sorted = [&](const std::vector<uint8_t>& v, size_t cnt) {
    std::vector<std::string> s(cnt);
    for (size_t i = 0; i < cnt; ++i)
      s[i].assign(reinterpret_cast<const char*>(&v[i * g->row_bytes]), g->row_bytes);
    std::sort(s.begin(), s.end());
    return s;
  };
  if (m != n || sorted(rows, n) != sorted(got, m)) g->multiset_exact = false;
}

// Codes frame f with the fewest position bits that keep it within bound, and adds its bytes and
// errors to the totals and the groups.
void run_frame(const capz::Take& t, size_t f, double bound, int speed, std::vector<Group>* groups,
               Totals* tot) {
  const std::vector<size_t> idx = finite_points(t, f);
  const size_t n = idx.size();
  if (n == 0) return;  // Draco cannot code an empty cloud; the frame costs nothing here
  std::vector<float> pos;
  const double range = frame_positions(t, f, idx, &pos);
  const FrameCloud c = build_cloud(t, f, idx, pos, *groups);
  for (int bits = first_bits(range, bound);; ++bits) {
    draco::EncoderBuffer buf;
    std::clock_t clocks[3];
    const std::unique_ptr<draco::PointCloud> out =
        code_frame(c, speed, bits, t.source, f, &buf, clocks);
    const bool kd = method_of(buf) == 1;
    const Pairing pr = pair_points(pos, decoded_positions(*out, n, kd, t.source, f), kd, bound);
    if (pr.emax > bound && bits < 30) continue;  // float rounding at the grid's edge: one more bit
    add_frame(buf.size(), n, kd, bits, pr, clocks, tot);
    const size_t m = out->num_points();
    for (size_t k = 0; k < groups->size(); ++k) {
      Group& g = (*groups)[k];
      const draco::PointAttribute* oa =
          out->GetAttributeByUniqueId(c.pc->attribute(c.ids[k])->unique_id());
      compare_rows(c.rows[k], decoded_rows(oa, g, m, t.source), n, m, pr, kd, &g);
    }
    return;
  }
}

int usage() {
  std::fprintf(stderr, "usage: capz_draco DIR --max-error B [--floats raw|bits] [--speed S]\n");
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return usage();
  double bound = 0;
  bool float_bits = false;
  int speed = 0;
  for (int i = 2; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--max-error" && i + 1 < argc) {
      bound = std::atof(argv[++i]);
    } else if (a == "--floats" && i + 1 < argc) {
      std::string v = argv[++i];
      if (v != "raw" && v != "bits") return usage();
      float_bits = v == "bits";
    } else if (a == "--speed" && i + 1 < argc) {
      speed = std::atoi(argv[++i]);
    } else {
      return usage();
    }
  }
  if (!(bound > 0) || speed < 0 || speed > 10) return usage();
  try {
    capz::Take t = capz::read_take(argv[1]);
    std::vector<Group> groups = plan(t, float_bits);
    Totals tot;
    for (size_t f = 0; f < t.frames; ++f) run_frame(t, f, bound, speed, &groups, &tot);
    bool organized = t.pcd && t.pcd->height > 1;
    std::printf(
        "{\"frames\": %zu, \"points\": %zu, \"kept_points\": %zu, \"dropped_points\": %zu,"
        " \"organized_dropped\": %s, \"bytes\": %zu, \"kd_tree_frames\": %zu,"
        " \"bits_min\": %d, \"bits_max\": %d, \"bound\": %s, \"pos_max_abs\": %s,"
        " \"pos_max_euclid\": %s, \"correspondence\": \"%s\", \"encode_s\": %.3f,"
        " \"decode_s\": %.3f, \"attributes\": [",
        t.frames, t.frames * t.points, tot.kept, t.frames * t.points - tot.kept,
        organized ? "true" : "false", tot.bytes, tot.kd_frames, tot.min_bits, tot.max_bits,
        capz_tools::json_num(bound).c_str(), capz_tools::json_num(tot.pos_max).c_str(),
        capz_tools::json_num(tot.pos_max_euclid).c_str(), tot.kd_frames == 0 ? "order" : "nearest",
        tot.enc_s, tot.dec_s);
    for (size_t k = 0; k < groups.size(); ++k) {
      const Group& g = groups[k];
      std::printf(
          "%s{\"name\": %s, \"draco\": %s, \"exact_points\": %zu, \"points\": %zu,"
          " \"max_abs\": %s, \"multiset_exact\": %s}",
          k ? ", " : "", capz_tools::json_str(g.name).c_str(),
          capz_tools::json_str(g.draco).c_str(), g.exact_points, g.points,
          capz_tools::json_num(g.max_abs).c_str(), g.multiset_exact ? "true" : "false");
    }
    std::printf("]}\n");
  } catch (const capz::Error& e) {
    std::fprintf(stderr, "capz_draco: %s\n", e.what());
    return static_cast<int>(e.code());
  }
  return 0;
}
