// capz_meta_dict [--dict FILE] FILE.capz...
// What a preset dictionary gives META (docs/FORMAT.md 5.8), on the META of .capz streams that
// capz wrote. Per stream, one tab-separated line:
//   file  payload  coding  fields  lzma2  dict1  [dictfile]
// payload: the META chunk's payload bytes as written; coding: its coding (0-3); fields: the bytes
// its coding codes; lzma2: coding 2's payload (no dictionary); dict1: coding 3's payload with
// dictionary 1; dictfile: the same with the bytes of FILE as the preset dictionary (a dictionary
// made without the file's own take, to measure what dictionary 1 gives a take it has not seen:
// tools/meta_dict_eval.sh). A last line sums each column over the streams.
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "capz/error.h"
#include "capz/file.h"
#include "coding/bytes.h"
#include "coding/container.h"
#include "coding/lzma_block.h"
#include "coding/meta.h"

using namespace capz;

namespace {

// Coding 2 or 3's payload size: coding byte, [dictionary byte], varint n, the LZMA2 stream.
size_t coded_size(const std::vector<uint8_t>& fields, LzmaPreset preset) {
  ByteWriter w;
  w.u8(preset.size ? 3 : 2);
  if (preset.size) w.u8(1);
  w.varint(fields.size());
  return w.buffer().size() + lzma2_encode(fields.data(), fields.size(), preset).size();
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<uint8_t> dict;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--dict") && i + 1 < argc)
      dict = read_file(argv[++i]);
    else
      files.push_back(argv[i]);
  }
  if (files.empty()) {
    std::fprintf(stderr, "usage: capz_meta_dict [--dict FILE] FILE.capz...\n");
    return 2;
  }
  uint64_t sum[5] = {};
  for (const std::string& path : files) {
    try {
      const std::vector<uint8_t> data = read_file(path);
      check_file_header(data.data(), data.size(), path);
      const int major = data[9];
      const Chunk head = read_chunk(data.data(), data.size(), file_header_bytes(major), path);
      const Chunk meta = read_chunk(data.data(), data.size(), head.end, path);
      if (meta.type != "META") fail(ErrorCode::kCorrupt, path, "no META after HEAD");
      const std::vector<uint8_t> fields = decode_meta_fields(meta, path, major);
      LzmaPreset own;
      own.data = dict.data();
      own.size = dict.size();
      const size_t row[5] = {meta.size, fields.size(), coded_size(fields, LzmaPreset()),
                             coded_size(fields, meta_dictionary(1)),
                             dict.empty() ? 0 : coded_size(fields, own)};
      std::printf("%s\t%zu\t%d\t%zu\t%zu\t%zu", path.c_str(), row[0], meta.payload[0], row[1],
                  row[2], row[3]);
      if (!dict.empty()) std::printf("\t%zu", row[4]);
      std::printf("\n");
      for (int k = 0; k < 5; ++k) sum[k] += row[k];
    } catch (const Error& e) {
      std::fprintf(stderr, "capz_meta_dict: %s\n", e.what());
      return 1;
    }
  }
  std::printf("total %zu streams\t%llu\t-\t%llu\t%llu\t%llu", files.size(),
              static_cast<unsigned long long>(sum[0]), static_cast<unsigned long long>(sum[1]),
              static_cast<unsigned long long>(sum[2]), static_cast<unsigned long long>(sum[3]));
  if (!dict.empty()) std::printf("\t%llu", static_cast<unsigned long long>(sum[4]));
  std::printf("\n");
  return 0;
}
