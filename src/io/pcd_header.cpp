// PCD frame headers (io/pcd_header.h).
#include "io/pcd_header.h"

#include <cctype>
#include <cstring>
#include <sstream>

#include "capz/error.h"
#include "io/text_number.h"

namespace capz {

namespace {

std::vector<std::string> words(const std::string& line) {
  std::vector<std::string> w;
  std::istringstream is(line);
  std::string s;
  while (is >> s) w.push_back(s);
  return w;
}

bool parse_u64(const std::string& s, uint64_t* out) {
  if (s.empty() || s.size() > 18) return false;
  uint64_t v = 0;
  for (char c : s) {
    if (c < '0' || c > '9') return false;
    v = v * 10 + static_cast<uint64_t>(c - '0');
  }
  *out = v;
  return true;
}

// Checks that the body after the header (at h.data_idx) can hold what the header announces, for
// its DATA type (binary, binary_compressed or ascii); fails on an unknown type.
void check_body_size(const std::vector<uint8_t>& bytes, const PcdHeader& h,
                     const std::string& name) {
  check_body_fits(bytes, bytes.size(), h, name);
}

}  // namespace

void check_body_fits(const std::vector<uint8_t>& bytes, uint64_t file_size, const PcdHeader& h,
                     const std::string& name) {
  const uint64_t body = file_size - h.data_idx;
  if (h.data == "binary") {
    if (h.point_step != 0 && h.points > body / h.point_step)
      fail(ErrorCode::kCorrupt, name,
           "PCD header announces " + std::to_string(h.points) + " points (" +
               std::to_string(h.points * h.point_step) + " bytes) but the body holds " +
               std::to_string(body) + " bytes");
  } else if (h.data == "binary_compressed") {
    if (body < 8 || bytes.size() < h.data_idx + 8)
      fail(ErrorCode::kCorrupt, name, "compressed PCD body is shorter than 8 bytes");
    const uint8_t* p = bytes.data() + h.data_idx;
    uint64_t csize = static_cast<uint64_t>(p[0]) | static_cast<uint64_t>(p[1]) << 8 |
                     static_cast<uint64_t>(p[2]) << 16 | static_cast<uint64_t>(p[3]) << 24;
    uint64_t usize = static_cast<uint64_t>(p[4]) | static_cast<uint64_t>(p[5]) << 8 |
                     static_cast<uint64_t>(p[6]) << 16 | static_cast<uint64_t>(p[7]) << 24;
    if (csize > body - 8)
      fail(ErrorCode::kCorrupt, name,
           "compressed PCD body says " + std::to_string(csize) + " bytes but the file holds " +
               std::to_string(body - 8));
    if (h.point_step != 0 && h.points > (uint64_t{1} << 32) / h.point_step)
      fail(ErrorCode::kCorrupt, name, "PCD header announces too many points for a compressed body");
    if (usize != h.points * h.point_step)
      fail(ErrorCode::kCorrupt, name,
           "compressed PCD body unpacks to " + std::to_string(usize) + " bytes, the header needs " +
               std::to_string(h.points * h.point_step));
    // LZF expands at most ~90x; anything above that cannot be a valid stream.
    if (usize > csize * 100 + 1024)
      fail(ErrorCode::kCorrupt, name, "compressed PCD body is too small for the points announced");
  } else if (h.data == "ascii") {
    // Every value takes at least one character and one separator.
    if (h.values_per_point != 0 && h.points > (body + 1) / (2 * h.values_per_point))
      fail(ErrorCode::kCorrupt, name,
           "PCD header announces " + std::to_string(h.points) +
               " points but the ASCII body is only " + std::to_string(body) + " bytes");
  } else {
    fail(ErrorCode::kCorrupt, name, "unknown PCD DATA type '" + h.data + "'");
  }
}

namespace {

// The values of a SIZE line (1, 2, 4 or 8 each), a TYPE line (F, I or U), a COUNT line (up to
// 2^20) and a VIEWPOINT line (7 numbers); w[0] is the key.
std::vector<int> sizes_of(const std::vector<std::string>& w, const std::string& name) {
  std::vector<int> v;
  for (size_t i = 1; i < w.size(); ++i) {
    uint64_t s;
    if (!parse_u64(w[i], &s) || (s != 1 && s != 2 && s != 4 && s != 8))
      fail(ErrorCode::kCorrupt, name, "PCD header: bad SIZE '" + w[i] + "'");
    v.push_back(static_cast<int>(s));
  }
  return v;
}
std::vector<char> types_of(const std::vector<std::string>& w, const std::string& name) {
  std::vector<char> v;
  for (size_t i = 1; i < w.size(); ++i) {
    // Not strchr("FIU", c): it finds the terminator when c is NUL.
    if (w[i].size() != 1 || (w[i][0] != 'F' && w[i][0] != 'I' && w[i][0] != 'U'))
      fail(ErrorCode::kCorrupt, name, "PCD header: bad TYPE '" + w[i] + "'");
    v.push_back(w[i][0]);
  }
  return v;
}
std::vector<uint64_t> counts_of(const std::vector<std::string>& w, const std::string& name) {
  std::vector<uint64_t> v;
  for (size_t i = 1; i < w.size(); ++i) {
    uint64_t c;
    if (!parse_u64(w[i], &c) || c > (1u << 20))
      fail(ErrorCode::kCorrupt, name, "PCD header: bad COUNT '" + w[i] + "'");
    v.push_back(c);
  }
  return v;
}
std::vector<double> viewpoint_of(const std::vector<std::string>& w, const std::string& name) {
  std::vector<double> v;
  for (size_t i = 1; i < w.size(); ++i) {
    double x;
    if (!parse_double(w[i], &x)) fail(ErrorCode::kCorrupt, name, "PCD header: bad VIEWPOINT");
    v.push_back(x);
  }
  if (v.size() != 7) fail(ErrorCode::kCorrupt, name, "PCD header: VIEWPOINT needs 7 values");
  return v;
}

// The checks and sums once every header line is read: FIELDS, SIZE, TYPE and COUNT of one
// length (COUNT defaults to 1s), WIDTH present and sane, POINTS = WIDTH x HEIGHT (its default),
// then the point step and the values per point.
void complete_header(PcdHeader* hp, bool have_width, bool have_points, const std::string& name) {
  PcdHeader& h = *hp;
  if (h.fields.empty()) fail(ErrorCode::kCorrupt, name, "PCD header has no FIELDS");
  if (h.counts.empty()) h.counts.assign(h.fields.size(), 1);
  if (h.sizes.size() != h.fields.size() || h.types.size() != h.fields.size() ||
      h.counts.size() != h.fields.size())
    fail(ErrorCode::kCorrupt, name, "PCD header: FIELDS, SIZE, TYPE and COUNT disagree in length");
  if (!have_width) fail(ErrorCode::kCorrupt, name, "PCD header has no WIDTH");
  // Each below 2^40 and so their product (which then cannot wrap around 2^64 either).
  if (h.width > (uint64_t{1} << 40) || h.height > (uint64_t{1} << 40) ||
      (h.height != 0 && h.width > (uint64_t{1} << 40) / h.height))
    fail(ErrorCode::kCorrupt, name, "PCD header: WIDTH x HEIGHT is absurd");
  if (!have_points) h.points = h.width * h.height;
  if (h.points != h.width * h.height)
    fail(ErrorCode::kCorrupt, name,
         "PCD header: POINTS " + std::to_string(h.points) + " is not WIDTH x HEIGHT " +
             std::to_string(h.width * h.height));
  for (size_t i = 0; i < h.fields.size(); ++i) {
    h.point_step += static_cast<uint64_t>(h.sizes[i]) * h.counts[i];
    h.values_per_point += h.counts[i];
  }
}

}  // namespace

PcdHeader parse_header(const std::vector<uint8_t>& bytes, const std::string& name) {
  PcdHeader h = parse_header_text(bytes, name);
  // The body must be able to hold what the header announces.
  check_body_size(bytes, h, name);
  return h;
}

PcdHeader parse_header_text(const std::vector<uint8_t>& bytes, const std::string& name) {
  PcdHeader h;
  size_t pos = 0;
  const size_t n = bytes.size();
  bool have_points = false, have_width = false;
  const size_t kMaxHeader = size_t{1} << 20;
  for (;;) {
    if (pos >= n || pos > kMaxHeader)
      fail(ErrorCode::kCorrupt, name, "PCD header has no DATA line");
    size_t e = pos;
    while (e < n && bytes[e] != '\n') ++e;
    std::string line(reinterpret_cast<const char*>(bytes.data()) + pos, e - pos);
    pos = e < n ? e + 1 : n;
    std::vector<std::string> w = words(line);
    if (w.empty() || w[0][0] == '#') continue;
    const std::string& k = w[0];
    auto one = [&](uint64_t* v) {
      if (w.size() < 2 || !parse_u64(w[1], v))
        fail(ErrorCode::kCorrupt, name, "PCD header: bad " + k + " line");
    };
    if (k == "VERSION") {
      if (w.size() >= 2) h.version = w[1];
    } else if (k == "VIEWPOINT") {
      h.viewpoint = viewpoint_of(w, name);
    } else if (k == "FIELDS" || k == "COLUMNS") {
      h.fields.assign(w.begin() + 1, w.end());
    } else if (k == "SIZE") {
      h.sizes = sizes_of(w, name);
    } else if (k == "TYPE") {
      h.types = types_of(w, name);
    } else if (k == "COUNT") {
      h.counts = counts_of(w, name);
    } else if (k == "WIDTH") {
      one(&h.width);
      have_width = true;
    } else if (k == "HEIGHT") {
      one(&h.height);
    } else if (k == "POINTS") {
      one(&h.points);
      have_points = true;
    } else if (k == "DATA") {
      if (w.size() < 2) fail(ErrorCode::kCorrupt, name, "PCD header: DATA line without a type");
      h.data = w[1];
      for (auto& c : h.data) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      h.data_idx = pos;
      break;
    } else {
      fail(ErrorCode::kNotOurFormat, name, "not a PCD file (unknown header line '" + k + "')");
    }
  }
  complete_header(&h, have_width, have_points, name);
  return h;
}

// PCL's ASCII body reader turns a bad token or a short line into zeros without a word, so the
// body is checked here first: after the header, every non-blank line holds exactly
// values_per_point numbers (nan allowed), and there are exactly `points` such lines.
void check_ascii_body(const std::vector<uint8_t>& bytes, const PcdHeader& h,
                      const std::string& name) {
  const char* p = reinterpret_cast<const char*>(bytes.data()) + h.data_idx;
  const char* end = reinterpret_cast<const char*>(bytes.data()) + bytes.size();
  uint64_t line_no = 0, rows = 0;
  std::string tok;
  while (p < end) {
    const char* nl = static_cast<const char*>(std::memchr(p, '\n', static_cast<size_t>(end - p)));
    const char* le = nl ? nl : end;
    ++line_no;
    uint64_t count = 0;
    for (const char* q = p; q < le;) {
      while (q < le && (*q == ' ' || *q == '\t' || *q == '\r')) ++q;
      if (q == le) break;
      const char* b = q;
      while (q < le && *q != ' ' && *q != '\t' && *q != '\r') ++q;
      tok.assign(b, q);
      double v;
      if (!parse_double(tok, &v))
        fail(ErrorCode::kCorrupt, name,
             "ASCII body line " + std::to_string(line_no) + ": '" + tok + "' is not a number");
      ++count;
    }
    if (count != 0) {
      if (count != h.values_per_point)
        fail(ErrorCode::kCorrupt, name,
             "ASCII body line " + std::to_string(line_no) + " holds " + std::to_string(count) +
                 " values, the header needs " + std::to_string(h.values_per_point));
      ++rows;
    }
    p = nl ? nl + 1 : end;
  }
  if (rows != h.points)
    fail(ErrorCode::kCorrupt, name,
         "ASCII body holds " + std::to_string(rows) + " points, the header says " +
             std::to_string(h.points));
}

}  // namespace capz
