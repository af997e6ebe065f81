// TRC (OpenSim / Motion Analysis "track row column") reader and writer.
//
// Layout read:
//   line 1  PathFileType <n> (X/Y/Z) <name>        (kept verbatim in TRCExtra)
//   line 2  DataRate CameraRate NumFrames NumMarkers Units OrigDataRate OrigDataStartFrame ...
//   line 3  the values of line 2's keys, matched by position
//   line 4  Frame# Time <name 1> <name 2> ...      (names = the non-empty fields after Time)
//   line 5  X1 Y1 Z1 X2 ...                        (column titles, ignored)
//   then    one row per frame: Frame# Time x1 y1 z1 x2 ...; blank lines are skipped.
// A line holding a tab is split at tabs (fields trimmed of blanks), otherwise at runs of blanks.
// A sample is valid when its three fields are numbers and finite; an empty field, NaN or a row
// that ends early makes a gap. Points = max(names on line 4, widest row); disagreement with
// NumMarkers / NumFrames becomes a warning in Take::warnings, not an error.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "capz/error.h"
#include "capz/io.h"
#include "core/atomic_file.h"
#include "io/text_number.h"
#include "io/trc_internal.h"

namespace capz {

namespace {

struct Field {
  const char* b;
  const char* e;
  bool empty() const { return b == e; }
  std::string str() const { return std::string(b, e); }
};

bool is_blank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\0' || c == '\f' || c == '\v';
}

// Splits [b, e) into fields (see the top of the file). Reuses `out`.
void split_fields(const char* b, const char* e, std::vector<Field>* out) {
  out->clear();
  bool tabs = std::memchr(b, '\t', static_cast<size_t>(e - b)) != nullptr;
  if (tabs) {
    const char* s = b;
    for (const char* p = b;; ++p) {
      if (p == e || *p == '\t') {
        const char* fb = s;
        const char* fe = p;
        while (fb < fe && is_blank(*fb)) ++fb;
        while (fe > fb && is_blank(fe[-1])) --fe;
        out->push_back({fb, fe});
        if (p == e) break;
        s = p + 1;
      }
    }
  } else {
    const char* p = b;
    while (p < e) {
      while (p < e && is_blank(*p)) ++p;
      if (p == e) break;
      const char* s = p;
      while (p < e && !is_blank(*p)) ++p;
      out->push_back({s, p});
    }
  }
}

// Lines of a text buffer, "\n" or "\r\n" terminated (a trailing '\r' is dropped).
class LineReader {
 public:
  LineReader(const char* data, size_t size) : p_(data), end_(data + size) {}
  bool next(const char** b, const char** e) {
    if (p_ >= end_) return false;
    const char* nl =
        static_cast<const char*>(std::memchr(p_, '\n', static_cast<size_t>(end_ - p_)));
    const char* le = nl ? nl : end_;
    *b = p_;
    *e = le;
    while (*e > *b && (*e)[-1] == '\r') --*e;
    p_ = nl ? nl + 1 : end_;
    ++number_;
    return true;
  }
  size_t number() const { return number_; }  // 1-based number of the last line returned
  const char* pos() const { return p_; }     // start of the next line

 private:
  const char* p_;
  const char* end_;
  size_t number_ = 0;
};

bool all_blank(const char* b, const char* e) {
  for (const char* p = b; p < e; ++p)
    if (!is_blank(*p)) return false;
  return true;
}

bool iequals(const std::string& a, const char* b) {
  size_t n = std::strlen(b);
  if (a.size() != n) return false;
  for (size_t i = 0; i < n; ++i)
    if (std::tolower(static_cast<unsigned char>(a[i])) !=
        std::tolower(static_cast<unsigned char>(b[i])))
      return false;
  return true;
}

// Digits after the decimal point of a plain decimal number; -1 with an exponent; 0 without '.'.
int decimals_of(const Field& f) {
  const char* dot = nullptr;
  for (const char* p = f.b; p < f.e; ++p) {
    if (*p == 'e' || *p == 'E') return -1;
    if (*p == '.') dot = p;
  }
  return dot ? static_cast<int>(f.e - dot - 1) : 0;
}

struct Header {
  double data_rate = 0, camera_rate = 0, orig_data_rate = 0;
  long num_frames = -1, num_markers = -1, orig_start = 1, orig_num_frames = 0;
  std::string units;
};

struct Counted {
  size_t rows = 0;
  size_t widest = 0;  // most coordinate triples holding a non-empty field in one row
};

}  // namespace

Take read_trc_bytes(const uint8_t* data, size_t size, const std::string& name) {
  if (size == 0) fail(ErrorCode::kNotOurFormat, name, "empty file (0 bytes), not a TRC file");
  const char* text = reinterpret_cast<const char*>(data);
  if (size >= 3 && std::memcmp(text, "\xEF\xBB\xBF", 3) == 0) {  // UTF-8 byte-order mark
    text += 3;
    size -= 3;
  }
  LineReader lines(text, size);
  const char* b = text;
  const char* e = text;
  std::vector<Field> f;

  // Line 1: PathFileType.
  lines.next(&b, &e);
  // "PathFileType", then tab- or blank-separated fields (both occur).
  std::string first(b, std::min<size_t>(static_cast<size_t>(e - b), 12));
  if (!iequals(first, "PathFileType"))
    fail(ErrorCode::kNotOurFormat, name,
         "not a TRC file (line 1 does not start with PathFileType)");
  auto trc = std::make_shared<TRCExtra>();
  trc->path_file_type_line.assign(b, e);

  // Lines 2 and 3: keys and values.
  if (!lines.next(&b, &e))
    fail(ErrorCode::kCorrupt, name, "file ends after line 1: the header keys (line 2) are missing");
  std::vector<Field> keys;
  split_fields(b, e, &keys);
  if (!lines.next(&b, &e))
    fail(ErrorCode::kCorrupt, name,
         "file ends after line 2: the header values (line 3) are missing");
  std::vector<Field> vals;
  split_fields(b, e, &vals);
  Header h;
  std::vector<std::string> warnings;
  for (size_t i = 0; i < keys.size(); ++i) {
    std::string k = keys[i].str();
    if (k.empty()) continue;
    std::string v = i < vals.size() ? vals[i].str() : std::string();
    auto num = [&](double* out) {
      double x;
      if (!parse_double(v, &x) || !std::isfinite(x))
        fail(ErrorCode::kCorrupt, name, "line 3: " + k + " '" + v + "' is not a number");
      *out = x;
    };
    auto integer = [&](long* out) {
      double x;
      num(&x);
      if (x != std::floor(x) || std::fabs(x) > 1e15)
        fail(ErrorCode::kCorrupt, name, "line 3: " + k + " '" + v + "' is not an integer");
      *out = static_cast<long>(x);
    };
    if (v.empty()) {
      warnings.push_back("header value of " + k + " is missing");
      continue;
    }
    if (iequals(k, "DataRate"))
      num(&h.data_rate);
    else if (iequals(k, "CameraRate"))
      num(&h.camera_rate);
    else if (iequals(k, "NumFrames"))
      integer(&h.num_frames);
    else if (iequals(k, "NumMarkers"))
      integer(&h.num_markers);
    else if (iequals(k, "Units"))
      h.units = v;
    else if (iequals(k, "OrigDataRate"))
      num(&h.orig_data_rate);
    else if (iequals(k, "OrigDataStartFrame"))
      integer(&h.orig_start);
    else if (iequals(k, "OrigNumFrames"))
      integer(&h.orig_num_frames);
  }

  // Line 4: Frame# Time names...
  if (!lines.next(&b, &e))
    fail(ErrorCode::kCorrupt, name,
         "file ends after line 3: the marker names (line 4) are missing");
  split_fields(b, e, &f);
  if (f.empty() || !iequals(f[0].str(), "Frame#"))
    fail(ErrorCode::kCorrupt, name, "line 4 should start with Frame# (the marker names line)");
  std::vector<std::string> names;
  for (size_t i = 2; i < f.size(); ++i)
    if (!f[i].empty()) names.push_back(f[i].str());
  // Line 5: X1 Y1 Z1 ... (ignored). A missing line 5 means a file with no rows.
  lines.next(&b, &e);
  const size_t data_line0 = lines.number() + 1;  // file line number of the first row line
  const char* data_start = lines.pos();

  // Pass 1: count rows and the widest row.
  Counted c;
  {
    LineReader rows(data_start, static_cast<size_t>(text + size - data_start));
    while (rows.next(&b, &e)) {
      if (all_blank(b, e)) continue;
      split_fields(b, e, &f);
      ++c.rows;
      size_t last = 0;
      for (size_t i = f.size(); i > 2; --i)
        if (!f[i - 1].empty()) {
          last = i - 1;
          break;
        }
      if (last >= 2) c.widest = std::max(c.widest, (last - 2) / 3 + 1);
    }
  }
  const size_t points = std::max(names.size(), c.widest);
  // Memory bound: a row that ends early costs no bytes but still takes `points` samples.
  // Legitimate files hold at least a few bytes per sample; refuse expansions beyond 8 samples
  // per byte of file.
  if (c.rows > 0 && points > 0 &&
      static_cast<double>(c.rows) * static_cast<double>(points) >
          8.0 * static_cast<double>(size) + 65536.0)
    fail(ErrorCode::kCorrupt, name,
         std::to_string(c.rows) + " rows x " + std::to_string(points) +
             " markers is far more than a file of " + std::to_string(size) + " bytes can hold");

  Take t;
  t.source = name;
  t.format = Format::kTRC;
  t.resize(c.rows, points);
  t.rate = h.data_rate;
  t.units = h.units;
  t.labels = names;
  t.labels.resize(points);
  trc->camera_rate = h.camera_rate;
  trc->orig_data_rate = h.orig_data_rate;
  trc->orig_data_start_frame = h.orig_start;
  trc->orig_num_frames = h.orig_num_frames;
  trc->times.reserve(c.rows);
  trc->frame_numbers.reserve(c.rows);

  // Pass 2: fill.
  size_t short_rows = 0, partial = 0, no_time = 0;
  int decimals = 0, time_decimals = 0;
  bool exponent = false, time_exponent = false;
  {
    LineReader rows(data_start, static_cast<size_t>(text + size - data_start));
    size_t r = 0;
    std::string tmp;
    while (rows.next(&b, &e)) {
      if (all_blank(b, e)) continue;
      const size_t line_no = data_line0 + rows.number() - 1;
      split_fields(b, e, &f);
      auto bad = [&](size_t col, const Field& fld, const char* what) {
        fail(ErrorCode::kCorrupt, name,
             "line " + std::to_string(line_no) + ", column " + std::to_string(col + 1) + ": '" +
                 fld.str() + "' is not " + what);
      };
      double frame_no = 0, time = 0;
      if (f.empty() || !parse_double(f[0].str(), &frame_no) || frame_no != std::floor(frame_no) ||
          std::fabs(frame_no) > 1e15)
        bad(0, f.empty() ? Field{b, b} : f[0], "a frame number");
      if (f.size() < 2 || f[1].empty()) {
        time = h.data_rate > 0 ? static_cast<double>(r) / h.data_rate : 0.0;
        ++no_time;
      } else if (!parse_double(f[1].str(), &time)) {
        bad(1, f[1], "a time");
      } else {
        int d = decimals_of(f[1]);
        if (d < 0) time_exponent = true;
        time_decimals = std::max(time_decimals, d);
      }
      trc->frame_numbers.push_back(static_cast<long>(frame_no));
      trc->times.push_back(time);
      if (f.size() < 2 + 3 * points) ++short_rows;
      for (size_t p = 0; p < points; ++p) {
        double v[3];
        int present = 0, finite = 0;
        for (int a = 0; a < 3; ++a) {
          size_t col = 2 + 3 * p + static_cast<size_t>(a);
          if (col >= f.size() || f[col].empty()) continue;
          ++present;
          if (!parse_double(f[col].str(), &v[a])) bad(col, f[col], "a number");
          if (std::isfinite(v[a])) {
            ++finite;
            int d = decimals_of(f[col]);
            if (d < 0) exponent = true;
            decimals = std::max(decimals, d);
          }
        }
        if (finite == 3) {
          double* dst = t.at(r, p);
          dst[0] = v[0];
          dst[1] = v[1];
          dst[2] = v[2];
          t.valid[r * points + p] = 1;
        } else if (present > 0 && present < 3) {
          ++partial;
        }
      }
      ++r;
    }
  }
  trc->decimals = exponent ? -1 : decimals;
  trc->time_decimals = time_exponent ? -1 : time_decimals;
  t.first_frame = trc->frame_numbers.empty() ? h.orig_start : trc->frame_numbers.front();

  if (h.num_frames >= 0 && static_cast<size_t>(h.num_frames) != c.rows)
    warnings.push_back("header says " + std::to_string(h.num_frames) + " frames, file holds " +
                       std::to_string(c.rows));
  if (h.num_markers >= 0 && static_cast<size_t>(h.num_markers) != points)
    warnings.push_back("header says " + std::to_string(h.num_markers) + " markers, file holds " +
                       std::to_string(points));
  if (names.size() != points)
    warnings.push_back(std::to_string(names.size()) + " marker names for " +
                       std::to_string(points) + " markers with data (" +
                       std::to_string(points - names.size()) + " unnamed)");
  if (short_rows > 0)
    warnings.push_back(std::to_string(short_rows) + " of " + std::to_string(c.rows) +
                       " rows end before the last marker (missing values read as gaps)");
  if (no_time > 0)
    warnings.push_back(std::to_string(no_time) +
                       " rows without a Time value (computed from DataRate)");
  if (partial > 0)
    warnings.push_back(std::to_string(partial) + " samples have only some of X/Y/Z (read as gaps)");
  if (h.data_rate <= 0) warnings.push_back("no DataRate: frame rate unknown");
  if (h.units.empty()) warnings.push_back("no Units in the header");
  t.warnings = std::move(warnings);
  t.trc = std::move(trc);
  return t;
}

Take read_trc(const std::string& path) {
  std::vector<uint8_t> bytes = read_file(path);
  return read_trc_bytes(bytes.data(), bytes.size(), path);
}

namespace trc {

std::string header_text(const Take& take, const std::string& path) {
  const TRCExtra* x = take.trc.get();
  const size_t F = take.frames, N = take.points;
  const double rate = take.rate;
  std::string s;
  s.reserve(64 + N * 32);
  if (x && !x->path_file_type_line.empty()) {
    s += x->path_file_type_line;
  } else {
    s += "PathFileType\t4\t(X/Y/Z)\t";
    s += std::filesystem::path(path).filename().string();
  }
  s += "\nDataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\tOrigDataStartFrame\t"
       "OrigNumFrames\n";
  s += format_decimal(rate, 2);
  s += '\t';
  s += format_decimal(x && x->camera_rate > 0 ? x->camera_rate : rate, 2);
  s += '\t' + std::to_string(F) + '\t' + std::to_string(N) + '\t';
  s += take.units.empty() ? std::string("mm") : take.units;
  s += '\t';
  s += format_decimal(x && x->orig_data_rate > 0 ? x->orig_data_rate : rate, 2);
  s += '\t' + std::to_string(x ? x->orig_data_start_frame : take.first_frame);
  s += '\t' +
       std::to_string(x && x->orig_num_frames > 0 ? static_cast<size_t>(x->orig_num_frames) : F);
  s += "\nFrame#\tTime";
  for (size_t p = 0; p < N; ++p) {
    s += '\t';
    const std::string& l = p < take.labels.size() ? take.labels[p] : std::string();
    s += l.empty() ? "M" + std::to_string(p + 1) : l;
    s += "\t\t";
  }
  s += "\n\t";
  for (size_t p = 0; p < N; ++p) {
    std::string i = std::to_string(p + 1);
    s += "\tX" + i + "\tY" + i + "\tZ" + i;
  }
  s += "\n\n";
  return s;
}

void append_rows(const Take& take, size_t first, size_t count, const double* xyz,
                 const uint8_t* valid, std::string* out) {
  const TRCExtra* x = take.trc.get();
  const size_t F = take.frames, N = take.points;
  const double rate = take.rate;
  const int dec = x ? x->decimals : -1;
  const int tdec = x && x->time_decimals >= 0 ? x->time_decimals : 3;
  const bool have_times = x && x->times.size() == F;
  const bool have_numbers = x && x->frame_numbers.size() == F;
  std::string& s = *out;
  for (size_t k = 0; k < count; ++k) {
    const size_t fr = first + k;
    s += std::to_string(have_numbers ? x->frame_numbers[fr]
                                     : take.first_frame + static_cast<long>(fr));
    s += '\t';
    double t = have_times ? x->times[fr] : (rate > 0 ? static_cast<double>(fr) / rate : 0.0);
    s += format_decimal(t, tdec);
    for (size_t p = 0; p < N; ++p) {
      if (!valid[k * N + p]) {
        s += "\t\t\t";
        continue;
      }
      const double* v = xyz + (k * N + p) * 3;
      for (int a = 0; a < 3; ++a) {
        s += '\t';
        s += format_decimal(v[a], dec);
      }
    }
    // A closing tab, as OpenSim writes: its reader drops an empty last field, so a row ending
    // in a gap would otherwise be one field short.
    s += "\t\n";
  }
}

}  // namespace trc

void write_trc(const Take& take, const std::string& path, const WriteOptions& opts) {
  const size_t F = take.frames, N = take.points;
  if (take.xyz.size() != F * N * 3 || take.valid.size() != F * N)
    fail(ErrorCode::kInternal, path, "take arrays do not match frames x points");
  // Output is created before formatting so an existing file is refused without work.
  AtomicFile out(path, opts.overwrite);
  std::string s = trc::header_text(take, path);
  constexpr size_t kRows = 256;  // rows formatted between writes
  for (size_t fr = 0; fr < F; fr += kRows) {
    const size_t n = std::min(kRows, F - fr);
    trc::append_rows(take, fr, n, take.xyz.data() + fr * N * 3, take.valid.data() + fr * N, &s);
    out.write(s.data(), s.size());
    s.clear();
  }
  out.write(s.data(), s.size());
  out.commit();
}

}  // namespace capz
