// The PCL side of the encoders' geometry, behind a small interface with no PCL types: pdct's
// nearest neighbours (pcl::KdTreeFLANN) and ts's rigid fit (pcl::registration's
// TransformationEstimationSVD). Both are encoder-only (what they find is stored in the stream).
//
// Why: libpcl_common and libpcl_kdtree, linked into capz, cost every capz process their loading
// and relocation (2026-11-29, medians of paired whole-process runs: an empty program linked
// against them 15 ms of CPU, unlinked 5 ms, on a loaded machine; `capz --version` 7 ms without
// them against 10 ms with, on a quiet one), for calls only those two encoders make. The
// implementation (src/modules/geom_pcl.cpp) is built as a module, libcapz_pcl_geom.so, next to
// the capz binary and installed beside libcapz_pcl_io.so; backend() opens it on first use.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace capz {
namespace geom {

class Backend {
 public:
  virtual ~Backend() = default;
  // For each of nq query points, the `want` points of `points` (n x 3 float32) nearest to it,
  // nearest first (pcl::KdTreeFLANN's sorted nearestKSearch): (*found)[q] of them (at most want)
  // at (*idx)[q * want ...]. Needs n >= 1 and 1 <= want <= n.
  virtual void knn(const float* points, size_t n, const float* queries, size_t nq, int want,
                   std::vector<int>* idx, std::vector<int>* found) const = 0;
  // The rigid transform (row-major 4 x 4) fitted by least squares (SVD) to take the n points
  // src onto tgt (each n x 3 float32).
  virtual void rigid(const float* src, const float* tgt, size_t n, double m[16]) const = 0;
};

// The module's entry point, a C symbol whose name carries the interface version.
#define CAPZ_GEOM_BACKEND_ENTRY capz_geom_backend_v1
using BackendEntry = const Backend* (*)();

// The backend, loaded on first use (thread-safe). Throws Error(kIo) naming `what` (the codec
// that needs it) when the module cannot be found or loaded.
const Backend& backend(const std::string& what);

}  // namespace geom
}  // namespace capz
