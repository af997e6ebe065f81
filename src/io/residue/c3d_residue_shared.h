// What the C3D residue's encoder (c3d_residue_encode.cpp) and decoder (c3d_residue.cpp) share
// (docs/FORMAT.md 7, 14.1); defined in c3d_residue.cpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "capz/error.h"
#include "capz/stream.h"
#include "capz/take.h"
#include "io/residue/c3d_residue.h"

namespace capz {
namespace residue {
namespace c3dr {

inline constexpr uint8_t kKindC3D = 1;  // C3DR's kind byte

size_t elem_size(const C3DFrameLayout& lay);
void to_processor_form(int processor, size_t elem, uint8_t* p, size_t n);
void to_processor_form(const C3DFrameLayout& lay, uint8_t* p, size_t n);
std::vector<uint8_t> dictionary(std::vector<C3DGroup> groups, int processor);
void check_block(const C3DFrameLayout& lay, const FrameBlock& b, const std::string& name,
                 ErrorCode code = ErrorCode::kInternal);
bool word4_negative(const C3DFrameLayout& lay, const uint8_t* q);
const std::vector<C3DGroup>& groups_of(const Take& t);

}  // namespace c3dr
}  // namespace residue
}  // namespace capz
