// The PCL side of PCD reading (PCL's PCDReader), behind a small interface with no PCL types, so
// that PCL's I/O library is loaded only when a PCD file is read (capz writes PCD files itself,
// io/pcd_frame_writer.h).
//
// Why: libpcl_io links VTK and about 60 other shared libraries; loading and relocating them
// cost every capz process about 22 ms of CPU (more than decoding a 40 s take), although only
// PCD folders need them. The implementation (src/modules/pcd_pcl.cpp) is built as a module,
// libcapz_pcl_io.so, next to the capz binary; pcd_backend() opens it with dlopen on first use.
// The module holds only what calls PCL; every check on the file stays in pcd_folder.cpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace capz {
namespace pcd {

// Field types (PCL's PCLPointField::PointFieldTypes, translated by the module).
enum class FieldType : uint8_t {
  kInt8,
  kUInt8,
  kInt16,
  kUInt16,
  kInt32,
  kUInt32,
  kInt64,
  kUInt64,
  kFloat32,
  kFloat64,
  kUnknown
};

struct Field {
  std::string name;
  uint32_t offset = 0;  // bytes into a point
  FieldType type = FieldType::kUnknown;
  uint32_t count = 1;
};

// One frame as PCL holds it: width x height points of point_step bytes each, little-endian.
struct Cloud {
  uint32_t width = 0, height = 1, point_step = 0;
  bool dense = true;  // no NaN point (written into the file's header only)
  std::vector<Field> fields;
  std::vector<uint8_t> data;
};

enum class Status {
  kOk,
  kHeaderRejected,  // PCL's readHeader failed
  kHeaderDiffers,   // PCL read other counts than the caller expected: the body was not read
  kBodyFailed,      // PCL's body reader returned an error
  kPclException,    // PCL threw pcl::PCLException (message set)
  kOtherException,  // PCL threw another std::exception (message set), e.g. a bad ASCII token
};

class Backend {
 public:
  virtual ~Backend() = default;
  // Reads the PCD file `bytes` (its header ends at byte data_idx) into *cloud. PCL's header is
  // checked against expect_points (width x height) and expect_step (point_step) before its body
  // is read, so PCL allocates only what the caller has checked against the file size.
  // std::bad_alloc propagates; every other failure is a Status (and *message).
  virtual Status read(const uint8_t* bytes, size_t size, size_t data_idx, uint64_t expect_points,
                      uint64_t expect_step, Cloud* cloud, std::string* message) const = 0;
};

// The module's entry point, a C symbol whose name carries the interface version.
#define CAPZ_PCD_BACKEND_ENTRY capz_pcd_backend_v2
using BackendEntry = const Backend* (*)();

// The backend, loaded on first use (thread-safe). Throws Error(kIo) naming `file` (the PCD file
// or folder being read or written) when the module cannot be found or loaded.
const Backend& backend(const std::string& file);

}  // namespace pcd
}  // namespace capz
