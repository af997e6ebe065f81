// capz — ascii PCD bodies by number style (see pcd_ascii.h; layout in docs/FORMAT.md 14.6).
#include "io/residue/pcd_ascii.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <map>
#include <string>

#include "capz/error.h"
#include "io/residue/mode.h"
#include "io/residue/pack.h"
#include "io/text_number.h"

namespace capz {
namespace residue {

namespace {

constexpr uint8_t kFixFields = 1, kWholeLine = 2, kNewEnding = 4;
constexpr uint8_t kColourAsFloat = 0x80;  // style bit: a packed colour's 4 bytes read as float32
constexpr size_t kMaxSep = 16, kMaxEnding = 16, kMaxNan = 64;
constexpr size_t kSamples = 256;  // values per column the style is chosen on

// One number of a point line: an element of a field, at `off` in the point record.
struct Column {
  size_t off = 0;
  char type = 'F';
  int size = 4;
  bool colour = false;  // a float32 rgb / rgba (the writer prints its bytes as an integer)
};

std::vector<Column> columns_of(const PcdFramePlan& plan, size_t* step) {
  std::vector<Column> cols;
  size_t off = 0;
  for (const PCDField& f : plan.layout.fields) {
    for (int k = 0; k < f.count; ++k) {
      if (f.name != "_")
        cols.push_back({off, f.type, f.size,
                        f.type == 'F' && f.size == 4 && f.count == 1 &&
                            (f.name == "rgb" || f.name == "rgba")});
      off += static_cast<size_t>(f.size);
    }
  }
  *step = off;
  return cols;
}

// Appends column c of the point at p in style byte `sb` (precision `prec`).
void append_column(const Column& c, const uint8_t* p, uint8_t sb, uint8_t prec,
                   const std::string& nan, std::string* out) {
  const uint8_t style = sb & 0x7F;
  p += c.off;
  if (c.type == 'F' && (!c.colour || (sb & kColourAsFloat))) {
    double v;
    if (c.size == 4) {
      float f;
      std::memcpy(&f, p, 4);
      v = f;
    } else {
      std::memcpy(&v, p, 8);
    }
    if (std::isnan(v))
      *out += nan;
    else if (std::isinf(v))
      *out += v < 0 ? "-inf" : "inf";
    else
      append_styled(v, c.size == 4, style, prec, out);
    return;
  }
  uint64_t u = 0;
  for (int i = 0; i < c.size; ++i) u |= static_cast<uint64_t>(p[i]) << (8 * i);
  char buf[32];
  if (c.type == 'I') {
    const int shift = 64 - 8 * c.size;
    const int64_t v = static_cast<int64_t>(u << shift) >> shift;
    if (style == kStyleShortest)
      out->append(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
    else
      append_styled(static_cast<double>(v), false, style, prec, out);
  } else if (style == kStyleShortest) {
    out->append(buf, std::to_chars(buf, buf + sizeof buf, u).ptr);
  } else {
    append_styled(static_cast<double>(u), false, style, prec, out);
  }
}

bool is_nan_column(const Column& c, const uint8_t* p) {
  if (c.type != 'F') return false;
  if (c.size == 4) {
    float f;
    std::memcpy(&f, p + c.off, 4);
    return std::isnan(f);
  }
  double d;
  std::memcpy(&d, p + c.off, 8);
  return std::isnan(d);
}

struct Span {
  const uint8_t* b;
  const uint8_t* e;
  std::string str() const { return std::string(b, e); }
  bool is(const std::string& s) const {
    return static_cast<size_t>(e - b) == s.size() && std::memcmp(b, s.data(), s.size()) == 0;
  }
};

// A body cut into n lines (content, ending) and what follows them.
struct Lines {
  std::vector<Span> content, ending;
  Span tail{nullptr, nullptr};
};

bool cut_lines(const uint8_t* body, size_t size, size_t n, Lines* out) {
  const uint8_t* p = body;
  const uint8_t* end = body + size;
  for (size_t i = 0; i < n; ++i) {
    const uint8_t* nl =
        static_cast<const uint8_t*>(std::memchr(p, '\n', static_cast<size_t>(end - p)));
    if (!nl && i + 1 < n) return false;
    const uint8_t* le = nl ? nl + 1 : end;
    const uint8_t* ce = nl ? nl : end;
    if (nl && ce > p && ce[-1] == '\r') --ce;
    out->content.push_back({p, ce});
    out->ending.push_back({ce, le});
    p = le;
  }
  out->tail = {p, end};
  return true;
}

void split_tokens(const Span& line, char sep, std::vector<Span>* out) {
  out->clear();
  const uint8_t* s = line.b;
  for (const uint8_t* q = line.b;; ++q) {
    if (q == line.e || *q == static_cast<uint8_t>(sep)) {
      out->push_back({s, q});
      if (q == line.e) break;
      s = q + 1;
    }
  }
}

// Decimals of a token's mantissa (after '.', before any exponent); 0 without a point.
uint8_t decimals_of(const Span& t) {
  const uint8_t* dot = nullptr;
  const uint8_t* q = t.b;
  for (; q < t.e && *q != 'e' && *q != 'E'; ++q)
    if (*q == '.') dot = q;
  const size_t d = dot ? static_cast<size_t>(q - dot - 1) : 0;
  return static_cast<uint8_t>(std::min<size_t>(d, kMaxStylePrecision));
}

// The style (byte, precision) reproducing the most of `samples` (token, point) of column c.
std::pair<uint8_t, uint8_t> choose_style(const Column& c,
                                         const std::vector<std::pair<Span, const uint8_t*>>& s,
                                         const std::string& nan) {
  std::vector<std::pair<uint8_t, uint8_t>> cands = {
      {kStyleShortest, 0}, {kStylePythonDouble, 0}, {kStylePythonShortest, 0}};
  for (uint8_t p = 1; p <= 17; ++p) cands.push_back({kStyleG, p});
  std::map<uint8_t, size_t> dec;
  for (const auto& x : s) ++dec[decimals_of(x.first)];
  for (const auto& kv : dec) {
    cands.push_back({kStyleE, kv.first});
    cands.push_back({kStyleF, kv.first});
  }
  if (c.colour) {
    const size_t plain = cands.size();
    for (size_t i = 0; i < plain; ++i)
      cands.push_back({static_cast<uint8_t>(cands[i].first | kColourAsFloat), cands[i].second});
  }
  std::pair<uint8_t, uint8_t> best = cands[0];
  size_t best_hits = 0;
  std::string text;
  for (const auto& cand : cands) {
    size_t hits = 0;
    for (const auto& x : s) {
      text.clear();
      append_column(c, x.second, cand.first, cand.second, nan, &text);
      hits += x.first.is(text);
    }
    if (hits > best_hits) best_hits = hits, best = cand;
  }
  return best;
}

char choose_separator(const std::vector<Span>& content, size_t cols) {
  if (content.empty()) return ' ';
  for (char c : {' ', '\t', ','})
    if (static_cast<size_t>(std::count(content[0].b, content[0].e, static_cast<uint8_t>(c))) + 1 ==
        cols)
      return c;
  return ' ';
}

}  // namespace

bool encode_ascii_body(const PcdFramePlan& plan, const uint8_t* points, size_t n,
                       const uint8_t* body, size_t size, ByteWriter* out) {
  size_t step = 0;
  const std::vector<Column> cols = columns_of(plan, &step);
  Lines lines;
  if (cols.empty() || n == 0 || !cut_lines(body, size, n, &lines)) return false;
  const size_t C = cols.size();
  const char sep = choose_separator(lines.content, C);
  // The line end, the NaN spelling and each column's samples, from lines of C fields.
  std::map<std::string, size_t> endings, nans;
  std::vector<std::vector<std::pair<Span, const uint8_t*>>> samples(C);
  std::vector<Span> tok;
  const size_t stride = std::max<size_t>(1, n / kSamples);
  for (size_t i = 0; i < n; ++i) {
    ++endings[lines.ending[i].str()];
    split_tokens(lines.content[i], sep, &tok);
    if (tok.size() != C) continue;
    const uint8_t* pt = points + i * step;
    for (size_t c = 0; c < C; ++c) {
      if (is_nan_column(cols[c], pt)) {
        if (nans.size() < 64 || nans.count(tok[c].str())) ++nans[tok[c].str()];
      } else if (i % stride == 0 && samples[c].size() < kSamples) {
        samples[c].push_back({tok[c], pt});
      }
    }
  }
  std::string eol = mode<std::string>(endings, "\n");
  if (eol.size() > kMaxEnding) eol = "\n";
  std::string nan = mode<std::string>(nans, "nan");
  if (nan.size() > kMaxNan) nan = "nan";
  std::vector<std::pair<uint8_t, uint8_t>> styles(C);
  for (size_t c = 0; c < C; ++c) styles[c] = choose_style(cols[c], samples[c], nan);

  ByteWriter ex;
  size_t count = 0, last = 0;
  std::string text;
  std::vector<size_t> starts(C + 1);
  std::vector<size_t> fix;
  for (size_t i = 0; i < n; ++i) {
    split_tokens(lines.content[i], sep, &tok);
    uint8_t flags = lines.ending[i].is(eol) ? 0 : kNewEnding;
    fix.clear();
    if (tok.size() != C) {
      flags |= kWholeLine;
    } else {
      const uint8_t* pt = points + i * step;
      for (size_t c = 0; c < C; ++c) {
        text.clear();
        append_column(cols[c], pt, styles[c].first, styles[c].second, nan, &text);
        if (!tok[c].is(text)) fix.push_back(c);
      }
      if (2 * fix.size() > C)
        flags |= kWholeLine;
      else if (!fix.empty())
        flags |= kFixFields;
    }
    if (!flags) continue;
    ++count;
    ex.varint(i - last);
    last = i;
    ex.u8(flags);
    if (flags & kWholeLine) {
      ex.str(lines.content[i].str());
    } else if (flags & kFixFields) {
      ex.varint(fix.size());
      for (size_t j = 0, prev = 0; j < fix.size(); prev = fix[j], ++j) {
        ex.varint(fix[j] - prev);
        ex.str(tok[fix[j]].str());
      }
    }
    if (flags & kNewEnding) ex.str(lines.ending[i].str());
  }
  ByteWriter packed;
  packed.varint(count);
  packed.bytes(ex.buffer());
  packed.str(lines.tail.str());
  out->varint(C);
  for (const auto& s : styles) {
    out->u8(s.first);
    out->u8(s.second);
  }
  out->str(std::string(1, sep));
  out->str(eol);
  out->str(nan);
  pack(packed.buffer(), {}, *out);
  return true;
}

void decode_ascii_body(const PcdFramePlan& plan, const uint8_t* points, size_t n, ByteReader& in,
                       uint64_t limit, const std::string& what, std::vector<uint8_t>* out) {
  size_t step = 0;
  const std::vector<Column> cols = columns_of(plan, &step);
  const size_t C = cols.size();
  if (in.varint() != C) fail(ErrorCode::kCorrupt, what, "ascii body: column count differs");
  std::vector<std::pair<uint8_t, uint8_t>> styles(C);
  for (size_t c = 0; c < C; ++c) {
    styles[c].first = in.u8();
    styles[c].second = in.u8();
    if ((styles[c].first & 0x7F) >= kNumberStyles || styles[c].second > kMaxStylePrecision ||
        ((styles[c].first & kColourAsFloat) && !cols[c].colour))
      fail(ErrorCode::kCorrupt, what, "ascii body: bad number style");
  }
  const std::string sep = in.str(), eol = in.str(), nan = in.str();
  if (sep.size() > kMaxSep || eol.size() > kMaxEnding || nan.size() > kMaxNan)
    fail(ErrorCode::kCorrupt, what, "ascii body: bad separator, line end or NaN text");
  const std::vector<uint8_t> packed = unpack(in, {}, 2 * limit + 65536);
  ByteReader ex(packed.data(), packed.size(), what + ": ascii body exceptions");
  uint64_t left = ex.count(2, "exceptions");
  uint64_t next = left ? ex.varint() : n;
  std::string line, text, ending;
  std::vector<std::string> fields(C);
  for (size_t i = 0; i < n; ++i) {
    const uint8_t* pt = points + i * step;
    for (size_t c = 0; c < C; ++c) {
      fields[c].clear();
      append_column(cols[c], pt, styles[c].first, styles[c].second, nan, &fields[c]);
    }
    line.clear();
    ending = eol;
    bool whole = false;
    if (i == next) {
      const uint8_t flags = ex.u8();
      if (flags == 0 || flags > 7 || ((flags & kWholeLine) && (flags & kFixFields)))
        fail(ErrorCode::kCorrupt, what, "ascii body: bad exception flags");
      if (flags & kWholeLine) line = ex.str(), whole = true;
      if (flags & kFixFields) {
        const uint64_t nfix = ex.count(2, "field fixes");
        for (uint64_t j = 0, c = 0; j < nfix; ++j) {
          c += ex.varint();
          if (c >= C) fail(ErrorCode::kCorrupt, what, "ascii body: field fix past the line");
          fields[static_cast<size_t>(c)] = ex.str();
        }
      }
      if (flags & kNewEnding) ending = ex.str();
      const uint64_t d = --left ? ex.varint() : n;
      if (left && d == 0) fail(ErrorCode::kCorrupt, what, "ascii body: exceptions out of order");
      next = left ? next + d : n;
    }
    if (!whole)
      for (size_t c = 0; c < C; ++c) {
        if (c) line += sep;
        line += fields[c];
      }
    out->insert(out->end(), line.begin(), line.end());
    out->insert(out->end(), ending.begin(), ending.end());
    if (out->size() > limit) fail(ErrorCode::kCorrupt, what, "ascii body longer than the file");
  }
  if (left) fail(ErrorCode::kCorrupt, what, "ascii body: exceptions past the last line");
  const std::string tail = ex.str();
  out->insert(out->end(), tail.begin(), tail.end());
  if (!ex.at_end()) fail(ErrorCode::kCorrupt, what, "ascii body: bytes left over");
}

}  // namespace residue
}  // namespace capz
