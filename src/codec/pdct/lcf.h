// pdct stage: local coordinate frames (Amjoun & Strasser 2007, Sec. 4.1.2 and Fig. 2).
//
// A frame is built on a triangle (p1, p2, p3): origin o at the midpoint of edge (p1, p2), x along
// p1 -> p2, y the component of (p3 - o) orthogonal to x (so y lies in the triangle's plane, on
// p3's side), z = x cross y. T holds the three unit axes as rows, so local q = T (p - o) and
// world p = T^T q + o. Both directions use only +, -, *, / and sqrt (IEEE correctly rounded), so
// encoder and decoder build bit-identical frames from identical triangle points.
#pragma once

namespace capz {
namespace pdct {

struct Lcf {
  double o[3] = {0, 0, 0};
  double t[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};  // row-major, rows = x, y, z axes
};

// Frame on triangle (p1, p2, p3), each a pointer to 3 doubles. Degenerate input does not fail:
// if |p2 - p1| is zero the x axis falls back to world x; if p3 is on the line the y axis falls
// back to the world axis least aligned with x (orthogonalised). The result is always orthonormal
// to rounding. (Triangle selection, seeds.h, keeps real triangles far from these cases.)
Lcf make_lcf(const double* p1, const double* p2, const double* p3);

// The identity frame (origin 0, world axes): used by a cluster that has no triangle.
inline Lcf identity_lcf() {
  return Lcf();
}

// q = T (p - o); p, q: 3 doubles (may not alias).
inline void to_local(const Lcf& f, const double* p, double* q) {
  const double d0 = p[0] - f.o[0], d1 = p[1] - f.o[1], d2 = p[2] - f.o[2];
  for (int r = 0; r < 3; ++r) q[r] = f.t[3 * r] * d0 + f.t[3 * r + 1] * d1 + f.t[3 * r + 2] * d2;
}
// p = T^T q + o; the inverse of to_local up to rounding (~1e-15 relative to |p - o|).
inline void to_world(const Lcf& f, const double* q, double* p) {
  for (int c = 0; c < 3; ++c)
    p[c] = (f.t[c] * q[0] + f.t[3 + c] * q[1] + f.t[6 + c] * q[2]) + f.o[c];
}

}  // namespace pdct
}  // namespace capz
