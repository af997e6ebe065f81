// Ascii PCD bodies coded by number style (see pcd_ascii.h; layout in docs/FORMAT.md 14.6): each
// column's style and precision found on a sample of its values, the separator and line endings,
// and the lines the styles do not rebuild; pcd_ascii.cpp is the decoder.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <map>
#include <string>

#include "capz/error.h"
#include "io/residue/mode.h"
#include "io/residue/pack.h"
#include "io/residue/pcd_ascii.h"
#include "io/residue/pcd_ascii_shared.h"
#include "io/text_number.h"

namespace capz {
namespace residue {

using namespace ascii;

namespace {

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

// A body cut into n lines (content, ending) and what follows them. A line's end is its '\n' with
// the '\r' and the blanks (spaces, tabs) before it: writers that put a separator after every
// value (Python's `print(*row, end=" \n")`, some C loops) end each line with " \n", which the
// model line then gives as its `eol` (FORMAT.md 14.6), the values as C columns.
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
    while (nl && ce > p && (ce[-1] == ' ' || ce[-1] == '\t')) --ce;
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

// What the body's lines mostly are: their line end, NaN spelling and each column's style.
struct AsciiConventions {
  std::string eol, nan;
  std::vector<std::pair<uint8_t, uint8_t>> styles;
};

// The line end, the NaN spelling and each column's style, from lines of C fields (step: a point's
// bytes in `points`).
AsciiConventions survey(const std::vector<Column>& cols, const Lines& lines, char sep,
                        const uint8_t* points, size_t step, size_t n) {
  const size_t C = cols.size();
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
  AsciiConventions a;
  a.eol = mode<std::string>(endings, "\n");
  if (a.eol.size() > kMaxEnding) a.eol = "\n";
  a.nan = mode<std::string>(nans, "nan");
  if (a.nan.size() > kMaxNan) a.nan = "nan";
  a.styles.resize(C);
  for (size_t c = 0; c < C; ++c) a.styles[c] = choose_style(cols[c], samples[c], a.nan);
  return a;
}

// Each line the conventions do not give back, into *ex: its distance from the last such line,
// its flags, then the whole line or the fields to fix, and its own line end. Returns their count.
size_t write_exceptions(const std::vector<Column>& cols, const Lines& lines, char sep,
                        const AsciiConventions& a, const uint8_t* points, size_t step, size_t n,
                        ByteWriter* ex) {
  const size_t C = cols.size();
  size_t count = 0, last = 0;
  std::string text;
  std::vector<Span> tok;
  std::vector<size_t> fix;
  for (size_t i = 0; i < n; ++i) {
    split_tokens(lines.content[i], sep, &tok);
    uint8_t flags = lines.ending[i].is(a.eol) ? 0 : kNewEnding;
    fix.clear();
    if (tok.size() != C) {
      flags |= kWholeLine;
    } else {
      const uint8_t* pt = points + i * step;
      for (size_t c = 0; c < C; ++c) {
        text.clear();
        append_column(cols[c], pt, a.styles[c].first, a.styles[c].second, a.nan, &text);
        if (!tok[c].is(text)) fix.push_back(c);
      }
      if (2 * fix.size() > C)
        flags |= kWholeLine;
      else if (!fix.empty())
        flags |= kFixFields;
    }
    if (!flags) continue;
    ++count;
    ex->varint(i - last);
    last = i;
    ex->u8(flags);
    if (flags & kWholeLine) {
      ex->str(lines.content[i].str());
    } else if (flags & kFixFields) {
      ex->varint(fix.size());
      for (size_t j = 0, prev = 0; j < fix.size(); prev = fix[j], ++j) {
        ex->varint(fix[j] - prev);
        ex->str(tok[fix[j]].str());
      }
    }
    if (flags & kNewEnding) ex->str(lines.ending[i].str());
  }
  return count;
}

}  // namespace

bool encode_ascii_body(const PcdFramePlan& plan, const uint8_t* points, size_t n,
                       const uint8_t* body, size_t size, ByteWriter* out) {
  size_t step = 0;
  const std::vector<Column> cols = columns_of(plan, &step);
  Lines lines;
  if (cols.empty() || n == 0 || !cut_lines(body, size, n, &lines)) return false;
  const char sep = choose_separator(lines.content, cols.size());
  const AsciiConventions a = survey(cols, lines, sep, points, step, n);
  ByteWriter ex;
  const size_t count = write_exceptions(cols, lines, sep, a, points, step, n, &ex);
  ByteWriter packed;
  packed.varint(count);
  packed.bytes(ex.buffer());
  packed.str(lines.tail.str());
  out->varint(cols.size());
  for (const auto& st : a.styles) {
    out->u8(st.first);
    out->u8(st.second);
  }
  out->str(std::string(1, sep));
  out->str(a.eol);
  out->str(a.nan);
  pack(packed.buffer(), {}, *out);
  return true;
}

}  // namespace residue
}  // namespace capz
