// C3D per-sample words of a window (docs/FORMAT.md 10): each sample's residual word and camera
// byte, coded by frame with an optional repeat flag per frame.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace capz {

// C3D residual (file units) and camera bytes of a window, frames x points each (3.5), with the
// window's gap mask `valid` (1 = valid). residual_on_grid (from residuals_on_grid()): every valid
// sample's residual is float32(k * point_scale) exactly and every gap's is -1 (mode 2, else
// mode 3). Each frame has a repeat flag.
std::vector<uint8_t> encode_c3d_words(const float* residual, const uint8_t* camera,
                                      const uint8_t* valid, size_t count, size_t points,
                                      double point_scale, bool residual_on_grid);
void decode_c3d_words(const uint8_t* data, size_t size, const uint8_t* valid, size_t count,
                      size_t points, double point_scale, float* residual, uint8_t* camera,
                      const std::string& what);
bool residuals_on_grid(const std::vector<float>& residual, const std::vector<uint8_t>& valid,
                       double point_scale);

// The residual of grid step k (mode 2), as encoder and decoder compute it.
inline float residual_from_grid(int32_t k, double scale) {
  return static_cast<float>(static_cast<double>(k) * scale);
}

}  // namespace capz
