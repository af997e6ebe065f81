// Decoder library (capz_decode): builds without PCL and without the transform encoders.
#include "codec/ts/ts_decoder.h"

#include "capz/error.h"
#include "codec/ts/ts_model.h"

namespace capz {

void TsDecoder::decode(const uint8_t* data, size_t size, size_t frames, size_t points,
                       std::vector<double>* recon) const {
  if (points > 0 && frames > (size_t{1} << 40) / points)
    fail(ErrorCode::kCorrupt, "ts payload", "window too large");
  ts::TsModel m = ts::read_model(data, size, frames, points);
  ts::reconstruct(m, recon);
}

}  // namespace capz
