// libcapz_pcl_io.so: PCD reading through PCL's PCDReader, loaded by capz with dlopen the
// first time a PCD file is read (interface and reasons in
// src/io/pcd_backend.h). Only PCL calls live here; capz's own checks of a file (header counts
// against the file size, the ASCII body's tokens) stay in src/io/pcd_folder.cpp.
// Nothing here throws capz::Error: failures are returned as a Status and a message.
#include <pcl/PCLPointCloud2.h>
#include <pcl/console/print.h>
#include <pcl/exceptions.h>
#include <pcl/io/pcd_io.h>

#include <sstream>
#include <string>

#include "io/pcd_backend.h"

namespace capz {
namespace pcd {
namespace {

// Silences PCL's console output for the lifetime of the object (PCL prints its own messages to
// stderr on bad files; capz reports errors itself). Restores the previous level.
class QuietPcl {
 public:
  QuietPcl() : saved_(pcl::console::getVerbosityLevel()) {
    pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  }
  ~QuietPcl() { pcl::console::setVerbosityLevel(saved_); }

 private:
  pcl::console::VERBOSITY_LEVEL saved_;
};

FieldType from_pcl(uint8_t t) {
  switch (t) {
    case pcl::PCLPointField::INT8:
      return FieldType::kInt8;
    case pcl::PCLPointField::UINT8:
      return FieldType::kUInt8;
    case pcl::PCLPointField::INT16:
      return FieldType::kInt16;
    case pcl::PCLPointField::UINT16:
      return FieldType::kUInt16;
    case pcl::PCLPointField::INT32:
      return FieldType::kInt32;
    case pcl::PCLPointField::UINT32:
      return FieldType::kUInt32;
    case pcl::PCLPointField::INT64:
      return FieldType::kInt64;
    case pcl::PCLPointField::UINT64:
      return FieldType::kUInt64;
    case pcl::PCLPointField::FLOAT32:
      return FieldType::kFloat32;
    case pcl::PCLPointField::FLOAT64:
      return FieldType::kFloat64;
  }
  return FieldType::kUnknown;
}

class PclBackend : public Backend {
 public:
  Status read(const uint8_t* bytes, size_t size, size_t data_idx, uint64_t expect_points,
              uint64_t expect_step, Cloud* out, std::string* message) const override {
    QuietPcl quiet;
    pcl::PCDReader reader;
    pcl::PCLPointCloud2 cloud;
    Eigen::Vector4f origin;
    Eigen::Quaternionf orientation;
    int version = 0, data_type = 0;
    unsigned int idx = 0;
    try {
      std::string head(reinterpret_cast<const char*>(bytes), data_idx);
      std::istringstream hs(head, std::ios::binary);
      if (reader.readHeader(hs, cloud, origin, orientation, version, data_type, idx) < 0)
        return Status::kHeaderRejected;
      if (cloud.width * static_cast<uint64_t>(cloud.height) != expect_points ||
          cloud.point_step != expect_step)
        return Status::kHeaderDiffers;
      int res;
      if (data_type == 0) {
        std::string body(reinterpret_cast<const char*>(bytes) + data_idx, size - data_idx);
        std::istringstream bs(body, std::ios::binary);
        res = reader.readBodyASCII(bs, cloud, version);
      } else {
        res = reader.readBodyBinary(bytes, cloud, version, data_type == 2,
                                    static_cast<unsigned int>(data_idx));
      }
      if (res < 0) return Status::kBodyFailed;
    } catch (const pcl::PCLException& e) {
      *message = e.what();
      return Status::kPclException;
    } catch (const std::bad_alloc&) {
      throw;
    } catch (const std::exception& e) {  // e.g. boost::bad_lexical_cast on an ASCII body
      *message = e.what();
      return Status::kOtherException;
    }
    out->width = cloud.width;
    out->height = cloud.height;
    out->point_step = cloud.point_step;
    out->dense = cloud.is_dense != 0;
    out->fields.clear();
    for (const pcl::PCLPointField& f : cloud.fields) {
      Field g;
      g.name = f.name;
      g.offset = f.offset;
      g.type = from_pcl(f.datatype);
      g.count = f.count;
      out->fields.push_back(g);
    }
    out->data = std::move(cloud.data);
    return Status::kOk;
  }
};

}  // namespace
}  // namespace pcd
}  // namespace capz

extern "C" __attribute__((visibility("default"))) const capz::pcd::Backend*
CAPZ_PCD_BACKEND_ENTRY() {
  static const capz::pcd::PclBackend backend;
  return &backend;
}
