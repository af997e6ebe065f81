// Lossless coding of one window of rotation samples (Rotations in take.h): the byte layout is
// docs/FORMAT.md 12. Every float32 comes back bit for bit (NaN payloads, -0.0,
// denormals, infinities included).
//
// Input shapes (one window of `samples` samples, sample-major as in take.h):
//   matrices    : samples x segments x 16 float32 (column-major 4x4 per segment)
//   reliability : samples x segments float32
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace capz {

// Element classes: each has its own predictor, contexts and escape models.
enum class RotationClass { kRotation = 0, kTranslation = 1, kBottomRow = 2, kReliability = 3 };
constexpr int kRotationClasses = 4;
// Class of element k of a sample of one segment: k = 0..15 the matrix (column-major), 16 the
// reliability.
RotationClass rotation_class(int k);

// Temporal predictors of one series (an element of one segment over the window's samples).
enum class RotationPredictor : uint8_t { kNone = 0, kPrevious = 1, kLinear = 2 };

std::vector<uint8_t> encode_rotations(const float* matrices, const float* reliability,
                                      size_t samples, size_t segments);

struct RotationWindow {
  std::vector<float> matrices;     // samples x segments x 16
  std::vector<float> reliability;  // samples x segments
};
// Decodes a window of `samples` x `segments` coded by encode_rotations. Throws Error(kCorrupt)
// naming `what` on a truncated or inconsistent block, bytes left over, or counts the block
// cannot hold (checked before allocating).
RotationWindow decode_rotations(const uint8_t* data, size_t size, size_t samples, size_t segments,
                                const std::string& what = "rotations");

}  // namespace capz
