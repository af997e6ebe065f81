// Analog channels of a window as formats 1-3 code them (docs/FORMAT.md 3.6): per channel a
// kind (integer, float32, float64) and one of four fixed predictors.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace capz {

// Analog samples of a window: rows x channels, row-major doubles (3.6). Kind per channel is
// chosen over the whole take by analog_kinds() so every window agrees.
std::vector<uint8_t> analog_kinds(const std::vector<double>& values, int channels);
// The same decision accumulated over consecutive blocks of whole rows (count values): start
// from `channels` kinds of 0 (integers) and feed the blocks in order.
void update_analog_kinds(const double* values, size_t count, int channels,
                         std::vector<uint8_t>* kinds);
std::vector<uint8_t> encode_analog(const double* rows, size_t nrows, int channels,
                                   const std::vector<uint8_t>& kinds);
void decode_analog(const uint8_t* data, size_t size, size_t nrows, int channels, double* rows,
                   const std::string& what);

}  // namespace capz
