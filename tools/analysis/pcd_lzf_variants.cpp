// Which LZF compressor wrote a PCD binary_compressed body? Decompresses the body of each file
// given and recompresses it with parameterised variants of liblzf's greedy compressor (hash
// table size, hash function, what is indexed after a match, whether offset 0 may be referenced),
// reporting for each variant the compressed size and the first byte that differs from the file's.
// Standalone (no capz library): g++ -O2 -std=c++17 pcd_lzf_variants.cpp -o pcd_lzf_variants
// Usage: pcd_lzf_variants [-only 'ultra hlog13 after1'] FILE.pcd...   Notes:
// docs/lab/2026-11-29-pcd-lzf-variants.md
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace {

using Bytes = std::vector<uint8_t>;

struct Variant {
  const char* name;
  int hlog;       // hash table of 1 << hlog slots
  int hash;       // 0: (h >> (24 - hlog)) - h; 1: ... - h * 5; 2: ((h ^ h << 5) >> ..) - h * 5;
                  // 3: (h * 0x1e35a7bd) >> (32 - hlog - 8)
  int after;      // positions indexed after a match: 1 (the last), 2 (the last two), -1 (all)
  bool ref_zero;  // whether a match may start at offset 0 of the input
};

uint32_t slot(uint32_t h, const Variant& v) {
  const uint32_t mask = (1u << v.hlog) - 1;
  switch (v.hash) {
    case 0:
      return ((h >> (24 - v.hlog)) - h) & mask;
    case 1:
      return ((h >> (24 - v.hlog)) - h * 5) & mask;
    case 2:
      return (((h ^ (h << 5)) >> (24 - v.hlog)) - h * 5) & mask;
    default:
      return ((h * 0x1e35a7bdu) >> (32 - v.hlog - 8)) & mask;
  }
}

// Literal runs go out as a control byte and up to 32 bytes.
struct Out {
  Bytes b;
  size_t lit_at = 0;
  int lit = 0;
  void start() {
    lit_at = b.size();
    b.push_back(0);
    lit = 0;
  }
  void close() {
    if (lit)
      b[lit_at] = static_cast<uint8_t>(lit - 1);
    else
      b.pop_back();
  }
  void literal(uint8_t c) {
    b.push_back(c);
    if (++lit == 32) {
      b[lit_at] = 31;
      start();
    }
  }
};

Bytes compress(const Bytes& in, const Variant& v) {
  const size_t n = in.size();
  std::vector<uint32_t> tab(size_t{1} << v.hlog, 0);
  Out o;
  o.start();
  size_t ip = 0;
  if (n < 3) {
    for (uint8_t c : in) o.literal(c);
    o.close();
    return o.b;
  }
  uint32_t h = static_cast<uint32_t>(in[0]) << 8 | in[1];
  while (ip + 2 < n) {
    h = h << 8 | in[ip + 2];
    uint32_t& s = tab[slot(h, v)];
    const size_t ref = s;
    s = static_cast<uint32_t>(ip);
    const bool ok = ref < ip && ip - ref - 1 < 8192 && (v.ref_zero || ref > 0) &&
                    in[ref] == in[ip] && in[ref + 1] == in[ip + 1] && in[ref + 2] == in[ip + 2];
    if (!ok) {
      o.literal(in[ip++]);
      continue;
    }
    size_t maxlen = n - ip - 2;
    if (maxlen > 264) maxlen = 264;
    size_t len = 2;
    // liblzf's unrolled first 16 comparisons run whenever maxlen > 16.
    bool stop = false;
    if (maxlen > 16)
      for (int k = 0; k < 16 && !stop; ++k) {
        ++len;
        stop = in[ref + len] != in[ip + len];
      }
    if (!stop) do
        ++len;
      while (len < maxlen && in[ref + len] == in[ip + len]);
    const size_t off = ip - ref - 1, l = len - 2;
    o.close();
    if (l < 7)
      o.b.push_back(static_cast<uint8_t>((off >> 8) + (l << 5)));
    else {
      o.b.push_back(static_cast<uint8_t>((off >> 8) + (7 << 5)));
      o.b.push_back(static_cast<uint8_t>(l - 7));
    }
    o.b.push_back(static_cast<uint8_t>(off & 255));
    o.start();
    const size_t end = ip + len;
    if (end + 2 >= n) {
      ip = end;
      break;
    }
    if (v.after < 0) {
      for (size_t p = ip + 1; p < end; ++p) {
        h = h << 8 | in[p + 2];
        tab[slot(h, v)] = static_cast<uint32_t>(p);
      }
    } else {
      size_t p = end - static_cast<size_t>(v.after);
      h = static_cast<uint32_t>(in[p]) << 8 | in[p + 1];
      for (; p < end; ++p) {
        h = h << 8 | in[p + 2];
        tab[slot(h, v)] = static_cast<uint32_t>(p);
      }
    }
    ip = end;
  }
  while (ip < n) o.literal(in[ip++]);
  o.close();
  return o.b;
}

bool decompress(const uint8_t* p, size_t n, size_t size, Bytes* out) {
  out->clear();
  size_t i = 0;
  while (i < n) {
    const size_t c = p[i++];
    if (c < 32) {
      if (i + c + 1 > n || out->size() + c + 1 > size) return false;
      out->insert(out->end(), p + i, p + i + c + 1);
      i += c + 1;
    } else {
      size_t len = (c >> 5) + 2;
      if ((c >> 5) == 7) {
        if (i >= n) return false;
        len += p[i++];
      }
      if (i >= n) return false;
      const size_t d = ((c & 31) << 8) + p[i++] + 1;
      if (d > out->size() || out->size() + len > size) return false;
      const size_t from = out->size() - d;
      for (size_t k = 0; k < len; ++k) out->push_back((*out)[from + k]);
    }
  }
  return out->size() == size;
}

uint32_t le32(const uint8_t* p) {
  return p[0] | static_cast<uint32_t>(p[1]) << 8 | static_cast<uint32_t>(p[2]) << 16 |
         static_cast<uint32_t>(p[3]) << 24;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<Variant> vs;
  static const char* hn[] = {"ultra", "very", "plain", "mul"};
  static std::vector<std::string> names;
  for (int hash = 0; hash < 4; ++hash)
    for (int hlog : {13, 14, 15, 16})
      for (int after : {1, 2, -1})
        for (int rz = 0; rz < 2; ++rz)
          names.push_back(std::string(hn[hash]) + " hlog" + std::to_string(hlog) + " after" +
                          std::to_string(after) + (rz ? " ref0" : ""));
  size_t q = 0;
  for (int hash = 0; hash < 4; ++hash)
    for (int hlog : {13, 14, 15, 16})
      for (int after : {1, 2, -1})
        for (int rz = 0; rz < 2; ++rz)
          vs.push_back({names[q++].c_str(), hlog, hash, after, rz == 1});
  // "-only NAME": just the variant NAME (e.g. "ultra hlog13 after1").
  int first = 1;
  if (argc > 2 && std::string(argv[1]) == "-only") {
    std::vector<Variant> keep;
    for (const Variant& v : vs)
      if (argv[2] == std::string(v.name)) keep.push_back(v);
    vs = keep;
    first = 3;
  }
  for (int a = first; a < argc; ++a) {
    std::ifstream f(argv[a], std::ios::binary);
    const Bytes file((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    const char* key = "DATA binary_compressed";
    const auto it = std::search(file.begin(), file.end(), key, key + std::strlen(key));
    if (it == file.end()) {
      std::printf("%s: not binary_compressed\n", argv[a]);
      continue;
    }
    size_t at = static_cast<size_t>(std::find(it, file.end(), '\n') - file.begin()) + 1;
    const uint32_t cs = le32(&file[at]), us = le32(&file[at + 4]);
    const uint8_t* body = &file[at + 8];
    Bytes raw;
    if (!decompress(body, cs, us, &raw)) {
      std::printf("%s: bad body\n", argv[a]);
      continue;
    }
    std::printf("%s: body %u -> %u bytes, trailing %zu\n", argv[a], cs, us,
                file.size() - at - 8 - cs);
    for (const Variant& v : vs) {
      const Bytes c = compress(raw, v);
      size_t d = 0;
      while (d < c.size() && d < cs && c[d] == body[d]) ++d;
      std::printf("  %-28s %9zu  %s at %zu\n", v.name, c.size(),
                  d == cs && c.size() == cs ? "MATCH" : "differs", d);
    }
  }
  return 0;
}
