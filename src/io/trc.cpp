// Decoder library (capz_decode): builds without PCL and without the transform encoders.
// TRC (OpenSim / Motion Analysis "track row column") reader and writer.
//
// Layout read:
//   line 1  PathFileType <n> (X/Y/Z) <name>        (kept verbatim in TRCExtra)
//   line 2  DataRate CameraRate NumFrames NumMarkers Units OrigDataRate OrigDataStartFrame ...
//   line 3  the values of line 2's keys, matched by position
//   line 4  Frame# Time <name 1> <name 2> ...      (names = the non-empty fields after Time)
//   line 5  X1 Y1 Z1 X2 ...                        (column titles, ignored)
//   then    one row per frame: Frame# Time x1 y1 z1 x2 ...; blank lines are skipped.
// A line holding a tab is split at tabs (fields trimmed of blanks), otherwise at runs of blanks;
// in a comma-separated file (trc::delimiter_of line 1: pyomeca's, a spreadsheet's) every line
// is split at commas (fields trimmed of blanks) and a line of only commas and blanks is blank.
// A sample is valid when its three fields are numbers and finite; an empty field, NaN or a row
// that ends early makes a gap. Points = max(names on line 4, widest row); disagreement with
// NumMarkers / NumFrames becomes a warning in Take::warnings, not an error.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "capz/error.h"
#include "capz/io.h"
#include "capz/stream.h"
#include "core/atomic_file.h"
#include "core/input_file.h"
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

// Splits [b, e) into fields (see the top of the file); `delim` is ',' in a comma-separated file,
// else '\t'. Reuses `out`.
void split_fields(const char* b, const char* e, char delim, std::vector<Field>* out) {
  out->clear();
  const char sep = delim == ',' ? ',' : '\t';
  if (sep == ',' || std::memchr(b, '\t', static_cast<size_t>(e - b)) != nullptr) {
    const char* s = b;
    for (const char* p = b;; ++p) {
      if (p == e || *p == sep) {
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

// A blank line: nothing but blanks (and, in a comma-separated file, commas).
bool all_blank(const char* b, const char* e, char delim) {
  for (const char* p = b; p < e; ++p)
    if (!is_blank(*p) && !(delim == ',' && *p == ',')) return false;
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
  int64_t num_frames = -1, num_markers = -1, orig_start = 1, orig_num_frames = 0;
  std::string units;
};

struct Counted {
  size_t rows = 0;
  size_t widest = 0;  // most coordinate triples holding a non-empty field in one row
};

// Pass 1 over one row line: counts it (blank lines are not rows) and its width.
void count_row(const char* b, const char* e, char delim, std::vector<Field>* f, Counted* c) {
  if (all_blank(b, e, delim)) return;
  split_fields(b, e, delim, f);
  ++c->rows;
  size_t last = 0;
  for (size_t i = f->size(); i > 2; --i)
    if (!(*f)[i - 1].empty()) {
      last = i - 1;
      break;
    }
  if (last >= 2) c->widest = std::max(c->widest, (last - 2) / 3 + 1);
}

// What lines 1..5 say, and where the rows start.
struct Prelude {
  Header h;
  std::vector<std::string> names;
  std::shared_ptr<TRCExtra> trc;
  std::vector<std::string> warnings;
  size_t bom = 0;          // bytes of a UTF-8 byte-order mark before line 1
  size_t data_offset = 0;  // offset of the first row line from the start of the text (after bom)
  size_t data_line0 = 0;   // its 1-based line number
  char delim = '\t';       // ',' in a comma-separated file (trc::delimiter_of line 1)
};

// Lines 2 and 3 of a TRC file: the header keys and their values, into pre->h (the keys capz
// knows; it skips the others) and pre->warnings (a key without a value). Throws as read_trc.
void read_header_values(const std::vector<Field>& keys, const std::vector<Field>& vals,
                        const std::string& name, Prelude* pre) {
  Header& h = pre->h;
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
    auto integer = [&](int64_t* out) {
      double x;
      num(&x);
      if (x != std::floor(x) || std::fabs(x) > 1e15)
        fail(ErrorCode::kCorrupt, name, "line 3: " + k + " '" + v + "' is not an integer");
      *out = static_cast<int64_t>(x);
    };
    if (v.empty()) {
      pre->warnings.push_back("header value of " + k + " is missing");
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
}

// Parses lines 1..5 of `text` (the file after any byte-order mark). Throws as read_trc.
Prelude parse_prelude(const char* text, size_t size, const std::string& name) {
  LineReader lines(text, size);
  const char* b = text;
  const char* e = text;
  std::vector<Field> f;
  Prelude pre;

  // Line 1: PathFileType.
  lines.next(&b, &e);
  // "PathFileType", then tab- or blank-separated fields (both occur).
  std::string first(b, std::min<size_t>(static_cast<size_t>(e - b), 12));
  if (!iequals(first, "PathFileType"))
    fail(ErrorCode::kNotOurFormat, name,
         "not a TRC file (line 1 does not start with PathFileType)");
  pre.trc = std::make_shared<TRCExtra>();
  pre.trc->path_file_type_line.assign(b, e);
  pre.delim = trc::delimiter_of(pre.trc->path_file_type_line);
  if (pre.delim == ',') trc::cut_padding(&pre.trc->path_file_type_line);
  const char d = pre.delim;

  // Lines 2 and 3: keys and values.
  if (!lines.next(&b, &e))
    fail(ErrorCode::kCorrupt, name, "file ends after line 1: the header keys (line 2) are missing");
  std::vector<Field> keys;
  split_fields(b, e, d, &keys);
  if (!lines.next(&b, &e))
    fail(ErrorCode::kCorrupt, name,
         "file ends after line 2: the header values (line 3) are missing");
  std::vector<Field> vals;
  split_fields(b, e, d, &vals);
  read_header_values(keys, vals, name, &pre);

  // Line 4: Frame# Time names...
  if (!lines.next(&b, &e))
    fail(ErrorCode::kCorrupt, name,
         "file ends after line 3: the marker names (line 4) are missing");
  split_fields(b, e, d, &f);
  if (f.empty() || !iequals(f[0].str(), "Frame#"))
    fail(ErrorCode::kCorrupt, name, "line 4 should start with Frame# (the marker names line)");
  for (size_t i = 2; i < f.size(); ++i)
    if (!f[i].empty()) pre.names.push_back(f[i].str());
  // Line 5: X1 Y1 Z1 ... (ignored). A missing line 5 means a file with no rows.
  lines.next(&b, &e);
  pre.data_line0 = lines.number() + 1;
  pre.data_offset = static_cast<size_t>(lines.pos() - text);
  return pre;
}

// Pass 2: one row line after another; what the rows say beyond their coordinates.
struct RowParser {
  size_t points = 0;
  double data_rate = 0;
  char delim = '\t';
  std::string name;
  size_t short_rows = 0, partial = 0, no_time = 0;
  int decimals = 0, time_decimals = 0;
  bool exponent = false, time_exponent = false;
  std::vector<Field> f;

  // Parses row r (a non-blank line, file line line_no): frame number, time and, when xyz is not
  // null, the samples (xyz: points x 3, valid: points; gaps left as they are).
  void parse(const char* b, const char* e, size_t line_no, size_t r, int64_t* frame_number,
             double* time_out, double* xyz, uint8_t* valid) {
    split_fields(b, e, delim, &f);
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
      time = data_rate > 0 ? static_cast<double>(r) / data_rate : 0.0;
      ++no_time;
    } else if (!parse_double(f[1].str(), &time)) {
      bad(1, f[1], "a time");
    } else {
      int d = decimals_of(f[1]);
      if (d < 0) time_exponent = true;
      time_decimals = std::max(time_decimals, d);
    }
    *frame_number = static_cast<int64_t>(frame_no);
    *time_out = time;
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
        if (xyz) {
          std::copy(v, v + 3, xyz + 3 * p);
          valid[p] = 1;
        }
      } else if (present > 0 && present < 3) {
        ++partial;
      }
    }
  }
};

// Refuses a row count and width that would expand a small file into a huge take: legitimate
// files hold at least a few bytes per sample; a row that ends early costs no bytes but still
// takes `points` samples.
void check_expansion(size_t rows, size_t points, size_t size, const std::string& name) {
  if (rows > 0 && points > 0 &&
      static_cast<double>(rows) * static_cast<double>(points) >
          8.0 * static_cast<double>(size) + 65536.0)
    fail(ErrorCode::kCorrupt, name,
         std::to_string(rows) + " rows x " + std::to_string(points) +
             " markers is far more than a file of " + std::to_string(size) + " bytes can hold");
}

// The take's metadata once every row has been parsed (frames, labels, TRC extra, warnings).
void finish_header(Prelude& pre, const RowParser& rp, size_t rows, Take* t) {
  const Header& h = pre.h;
  const size_t points = rp.points;
  t->source = rp.name;
  t->format = Format::kTRC;
  t->frames = rows;
  t->points = points;
  t->rate = h.data_rate;
  t->units = h.units;
  t->labels = pre.names;
  t->labels.resize(points);
  TRCExtra& trc = *pre.trc;
  trc.camera_rate = h.camera_rate;
  trc.orig_data_rate = h.orig_data_rate;
  trc.orig_data_start_frame = h.orig_start;
  trc.orig_num_frames = h.orig_num_frames;
  trc.decimals = rp.exponent ? -1 : rp.decimals;
  trc.time_decimals = rp.time_exponent ? -1 : rp.time_decimals;
  t->first_frame = trc.frame_numbers.empty() ? h.orig_start : trc.frame_numbers.front();
  std::vector<std::string> warnings = pre.warnings;
  if (h.num_frames >= 0 && static_cast<size_t>(h.num_frames) != rows)
    warnings.push_back("header says " + std::to_string(h.num_frames) + " frames, file holds " +
                       std::to_string(rows));
  if (h.num_markers >= 0 && static_cast<size_t>(h.num_markers) != points)
    warnings.push_back("header says " + std::to_string(h.num_markers) + " markers, file holds " +
                       std::to_string(points));
  if (pre.names.size() != points)
    warnings.push_back(std::to_string(pre.names.size()) + " marker names for " +
                       std::to_string(points) + " markers with data (" +
                       std::to_string(points - pre.names.size()) + " unnamed)");
  if (rp.short_rows > 0)
    warnings.push_back(std::to_string(rp.short_rows) + " of " + std::to_string(rows) +
                       " rows end before the last marker (missing values read as gaps)");
  if (rp.no_time > 0)
    warnings.push_back(std::to_string(rp.no_time) +
                       " rows without a Time value (computed from DataRate)");
  if (rp.partial > 0)
    warnings.push_back(std::to_string(rp.partial) +
                       " samples have only some of X/Y/Z (read as gaps)");
  if (h.data_rate <= 0) warnings.push_back("no DataRate: frame rate unknown");
  if (h.units.empty()) warnings.push_back("no Units in the header");
  t->warnings = std::move(warnings);
  t->trc = pre.trc;
}

size_t bom_bytes(const uint8_t* data, size_t size) {
  return size >= 3 && std::memcmp(data, "\xEF\xBB\xBF", 3) == 0 ? 3 : 0;
}

// Lines of a file read a chunk at a time (LineReader's rules), with the file offset of each.
class FileLines {
 public:
  FileLines(InputFile* file, uint64_t offset) : file_(file), pos_(offset) {}
  bool next(const char** b, const char** e, uint64_t* offset) {
    for (;;) {
      const char* nl = static_cast<const char*>(std::memchr(buf_.data() + cur_, '\n', end_ - cur_));
      if (nl || eof_) {
        if (cur_ >= end_ && !nl) return false;
        const char* le = nl ? nl : buf_.data() + end_;
        *b = buf_.data() + cur_;
        *e = le;
        while (*e > *b && (*e)[-1] == '\r') --*e;
        *offset = buf_off_ + cur_;
        cur_ = nl ? static_cast<size_t>(nl - buf_.data()) + 1 : end_;
        return true;
      }
      refill();
    }
  }

 private:
  void refill() {  // keeps the unread part, appends the next chunk
    const size_t keep = end_ - cur_;
    std::memmove(buf_.data(), buf_.data() + cur_, keep);
    buf_off_ += cur_;
    cur_ = 0;
    end_ = keep;
    const uint64_t left = file_->size() - pos_;
    const size_t want = static_cast<size_t>(std::min<uint64_t>(left, kChunk));
    if (buf_.size() < keep + want + 1) buf_.resize(std::max(buf_.size() * 2, keep + want + 1));
    file_->read_at(pos_, buf_.data() + end_, want);
    pos_ += want;
    end_ += want;
    if (pos_ >= file_->size()) eof_ = true;
  }

  static constexpr size_t kChunk = size_t{1} << 20;
  InputFile* file_;
  uint64_t pos_;  // next file offset to read
  std::vector<char> buf_ = std::vector<char>(1);
  uint64_t buf_off_ = pos_;   // file offset of buf_[0]
  size_t cur_ = 0, end_ = 0;  // unread lines are buf_[cur_, end_)
  bool eof_ = false;
};

// A TRC read by frame ranges: opening reads every line once (the point count, decimals and
// the Time column need all of them) keeping only the per-row metadata and each row's offset;
// a range reads and parses just its rows.
class TRCSource : public FrameSource {
 public:
  explicit TRCSource(const std::string& path) : file_(path) {
    const uint64_t size = file_.size();
    if (size == 0) fail(ErrorCode::kNotOurFormat, path, "empty file (0 bytes), not a TRC file");
    // Lines 1..5: read until five line ends are in (or the file ends).
    std::vector<uint8_t> head;
    size_t lines = 0;
    while (lines < 5 && head.size() < size) {
      const size_t had = head.size();
      const size_t more =
          static_cast<size_t>(std::min<uint64_t>(size - had, std::max<size_t>(had, 65536)));
      head.resize(had + more);
      file_.read_at(had, head.data() + had, more);
      lines +=
          static_cast<size_t>(std::count(head.begin() + static_cast<long>(had), head.end(), '\n'));
    }
    bom_ = bom_bytes(head.data(), head.size());
    Prelude pre =
        parse_prelude(reinterpret_cast<const char*>(head.data()) + bom_, head.size() - bom_, path);
    const uint64_t start = bom_ + pre.data_offset;
    Counted c;
    {
      FileLines rows(&file_, start);
      const char *b, *e;
      uint64_t off;
      std::vector<Field> f;
      while (rows.next(&b, &e, &off)) count_row(b, e, pre.delim, &f, &c);
    }
    parser_.points = std::max(pre.names.size(), c.widest);
    parser_.data_rate = pre.h.data_rate;
    parser_.delim = pre.delim;
    parser_.name = path;
    check_expansion(c.rows, parser_.points, static_cast<size_t>(size) - bom_, path);
    TRCExtra& trc = *pre.trc;
    trc.times.reserve(c.rows);
    trc.frame_numbers.reserve(c.rows);
    offsets_.reserve(c.rows + 1);
    {
      FileLines rows(&file_, start);
      const char *b, *e;
      uint64_t off;
      size_t line_no = pre.data_line0 - 1;
      while (rows.next(&b, &e, &off)) {
        ++line_no;
        if (all_blank(b, e, pre.delim)) continue;
        int64_t fn;
        double t;
        parser_.parse(b, e, line_no, offsets_.size(), &fn, &t, nullptr, nullptr);
        trc.frame_numbers.push_back(fn);
        trc.times.push_back(t);
        offsets_.push_back(off);
        line_numbers_.push_back(line_no);
      }
    }
    offsets_.push_back(size);
    finish_header(pre, parser_, offsets_.size() - 1, &header_);
  }
  bool has_sample_words() const override { return false; }
  void read(size_t first, size_t count, FrameBlock* out) override {
    const size_t N = header_.points;
    clip(&first, &count);
    out->reset(first, count, N, 0, false);
    if (count == 0) return;
    buf_.resize(static_cast<size_t>(offsets_[first + count] - offsets_[first]));
    file_.read_at(offsets_[first], buf_.data(), buf_.size());
    LineReader lines(buf_.data(), buf_.size());
    const char *b, *e;
    size_t r = 0;
    RowParser rp = parser_;  // counters of the open pass stay as they were
    while (r < count && lines.next(&b, &e)) {
      if (all_blank(b, e, rp.delim)) continue;
      int64_t fn;
      double t;
      rp.parse(b, e, line_numbers_[first + r], first + r, &fn, &t, &out->xyz[r * N * 3],
               &out->valid[r * N]);
      ++r;
    }
    if (r != count) fail(ErrorCode::kIo, header_.source, "file changed while reading");
  }
  uint64_t bytes_read() const override { return file_.bytes_read(); }
  std::string original_file() const override { return file_.path(); }

 private:
  InputFile file_;
  size_t bom_ = 0;
  RowParser parser_;
  std::vector<uint64_t> offsets_;     // file offset of each row line, then the file size
  std::vector<size_t> line_numbers_;  // each row's line number (for messages)
  std::vector<char> buf_;
};

}  // namespace

Take read_trc_bytes(const uint8_t* data, size_t size, const std::string& name) {
  if (size == 0) fail(ErrorCode::kNotOurFormat, name, "empty file (0 bytes), not a TRC file");
  const size_t bom = bom_bytes(data, size);
  const char* text = reinterpret_cast<const char*>(data) + bom;
  size -= bom;
  Prelude pre = parse_prelude(text, size, name);
  const char* data_start = text + pre.data_offset;
  const size_t rows_size = static_cast<size_t>(text + size - data_start);
  const char* b = text;
  const char* e = text;

  // Pass 1: count rows and the widest row.
  Counted c;
  {
    std::vector<Field> f;
    LineReader rows(data_start, rows_size);
    while (rows.next(&b, &e)) count_row(b, e, pre.delim, &f, &c);
  }
  RowParser rp;
  rp.points = std::max(pre.names.size(), c.widest);
  rp.data_rate = pre.h.data_rate;
  rp.delim = pre.delim;
  rp.name = name;
  check_expansion(c.rows, rp.points, size, name);

  // Pass 2: fill.
  Take t;
  t.resize(c.rows, rp.points);
  TRCExtra& trc = *pre.trc;
  trc.times.reserve(c.rows);
  trc.frame_numbers.reserve(c.rows);
  {
    LineReader rows(data_start, rows_size);
    size_t r = 0;
    while (rows.next(&b, &e)) {
      if (all_blank(b, e, rp.delim)) continue;
      int64_t fn;
      double time;
      rp.parse(b, e, pre.data_line0 + rows.number() - 1, r, &fn, &time,
               rp.points ? t.at(r, 0) : nullptr, rp.points ? &t.valid[r * rp.points] : nullptr);
      trc.frame_numbers.push_back(fn);
      trc.times.push_back(time);
      ++r;
    }
  }
  finish_header(pre, rp, c.rows, &t);
  return t;
}

Take read_trc(const std::string& path) {
  std::vector<uint8_t> bytes = read_file(path);
  return read_trc_bytes(bytes.data(), bytes.size(), path);
}

std::unique_ptr<FrameSource> open_trc_frames(const std::string& path) {
  return std::unique_ptr<FrameSource>(new TRCSource(path));
}

}  // namespace capz
