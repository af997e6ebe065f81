// Decoder library (capz_decode): builds without PCL and without the transform encoders.
// TRC writer: the OpenSim form (tab-separated, a closing tab on each row) or the comma form a
// spreadsheet saves (every line padded with commas to the widest line's field count, no closing
// comma). Which one: WriteOptions::trc_delimiter, else the take's own (trc::take_delimiter).
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "capz/error.h"
#include "capz/io.h"
#include "core/atomic_file.h"
#include "io/text_number.h"
#include "io/trc_internal.h"

namespace capz {
namespace trc {

namespace {

// Fields of a line split at `sep` (no trimming); sep ' ' splits at runs of blanks.
std::vector<std::string> split_at(const std::string& line, char sep) {
  std::vector<std::string> out;
  if (sep == ' ') {
    size_t p = 0;
    while (p < line.size()) {
      while (p < line.size() && (line[p] == ' ' || line[p] == '\t')) ++p;
      if (p == line.size()) break;
      const size_t s = p;
      while (p < line.size() && line[p] != ' ' && line[p] != '\t') ++p;
      out.push_back(line.substr(s, p - s));
    }
    return out;
  }
  for (size_t s = 0;;) {
    const size_t t = line.find(sep, s);
    out.push_back(line.substr(s, t == std::string::npos ? std::string::npos : t - s));
    if (t == std::string::npos) break;
    s = t + 1;
  }
  return out;
}

// The take's line 1 spelled with `delim` (its own text when it already is; see header_text).
std::string first_line(const Take& take, const std::string& path, char delim) {
  const TRCExtra* x = take.trc.get();
  if (!x || x->path_file_type_line.empty()) {
    const std::string name = std::filesystem::path(path).filename().string();
    return std::string("PathFileType") + delim + "4" + delim + "(X/Y/Z)" + delim + name;
  }
  const std::string& line = x->path_file_type_line;
  const char own = delimiter_of(line);
  if (own == delim) return line;
  if (delim == '\t' && own != ',') return line;  // OpenSim's blank-separated variants stay
  std::vector<std::string> f =
      split_at(line, own == ',' ? ',' : (line.find('\t') != std::string::npos ? '\t' : ' '));
  while (f.size() > 1 && f.back().find_first_not_of(" \t\r") == std::string::npos) f.pop_back();
  std::string s;
  for (size_t i = 0; i < f.size(); ++i) s += (i ? std::string(1, delim) : std::string()) + f[i];
  return s;
}

// Appends the commas that pad a comma-form line of `fields` fields to `width`.
void pad(std::string* s, size_t fields, size_t width) {
  if (fields < width) s->append(width - fields, ',');
}

size_t fields_of(const std::string& line, char delim) {
  return static_cast<size_t>(std::count(line.begin(), line.end(), delim)) + 1;
}

}  // namespace

char delimiter_of(const std::string& path_file_type_line) {
  const std::string& l = path_file_type_line;
  if (l.find('\t') != std::string::npos) return '\t';
  return (l.size() > 12 && l[12] == ',') || (!l.empty() && l.back() == ',') ? ',' : '\t';
}

void cut_padding(std::string* line) {
  std::string& l = *line;
  while (!l.empty() && l.back() == ',') {
    l.pop_back();
    if (delimiter_of(l) == ',') continue;
    l.push_back(',');  // the last comma says the line is comma-separated
    break;
  }
}

char take_delimiter(const Take& take) {
  return take.trc ? delimiter_of(take.trc->path_file_type_line) : '\t';
}

char output_delimiter(const Take& take, char asked, const std::string& path) {
  if (asked == 0) return take_delimiter(take);
  if (asked != '\t' && asked != ',')
    fail(ErrorCode::kInvalidParameter, path, "a TRC is written with tabs or commas");
  return asked;
}

size_t comma_width(const Take& take, const std::string& path) {
  return std::max<size_t>({8, 2 + 3 * take.points, fields_of(first_line(take, path, ','), ',')});
}

std::string header_text(const Take& take, const std::string& path, char delim) {
  return header_text(take, path, delim, delim == ',' ? comma_width(take, path) : 0, "\n");
}

std::string header_text(const Take& take, const std::string& path, char delim, size_t width,
                        const std::string& eol) {
  const TRCExtra* x = take.trc.get();
  const size_t F = take.frames, N = take.points;
  const double rate = take.rate;
  const std::string d(1, delim);
  const bool comma = delim == ',';
  std::string s;
  s.reserve(64 + N * 32);
  const std::string line1 = first_line(take, path, delim);
  s += line1;
  if (comma) pad(&s, fields_of(line1, ','), width);
  s += eol + "DataRate" + d + "CameraRate" + d + "NumFrames" + d + "NumMarkers" + d + "Units" + d +
       "OrigDataRate" + d + "OrigDataStartFrame" + d + "OrigNumFrames";
  if (comma) pad(&s, 8, width);
  s += eol;
  s += format_decimal(rate, 2);
  s += d + format_decimal(x && x->camera_rate > 0 ? x->camera_rate : rate, 2);
  s += d + std::to_string(F) + d + std::to_string(N) + d;
  s += take.units.empty() ? std::string("mm") : take.units;
  s += d + format_decimal(x && x->orig_data_rate > 0 ? x->orig_data_rate : rate, 2);
  s += d + std::to_string(x ? x->orig_data_start_frame : take.first_frame);
  s +=
      d + std::to_string(x && x->orig_num_frames > 0 ? static_cast<size_t>(x->orig_num_frames) : F);
  if (comma) pad(&s, 8, width);
  s += eol + "Frame#" + d + "Time";
  for (size_t p = 0; p < N; ++p) {
    s += d;
    const std::string& l = p < take.labels.size() ? take.labels[p] : std::string();
    s += l.empty() ? "M" + std::to_string(p + 1) : l;
    s += d + d;
  }
  if (comma) pad(&s, 2 + 3 * N, width);
  s += eol + d;
  for (size_t p = 0; p < N; ++p) {
    std::string i = std::to_string(p + 1);
    s += d + "X" + i + d + "Y" + i + d + "Z" + i;
  }
  if (comma) pad(&s, 2 + 3 * N, width);
  s += eol;
  if (comma) pad(&s, 1, width);  // the blank line: only its commas
  s += eol;
  return s;
}

void append_rows(const Take& take, size_t first, size_t count, const double* xyz,
                 const uint8_t* valid, char delim, size_t width, std::string* out) {
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
                                     : take.first_frame + static_cast<int64_t>(fr));
    s += delim;
    double t = have_times ? x->times[fr] : (rate > 0 ? static_cast<double>(fr) / rate : 0.0);
    s += format_decimal(t, tdec);
    for (size_t p = 0; p < N; ++p) {
      if (!valid[k * N + p]) {
        s.append(3, delim);
        continue;
      }
      const double* v = xyz + (k * N + p) * 3;
      for (int a = 0; a < 3; ++a) {
        s += delim;
        s += format_decimal_rounded(v[a], dec);  // = format_decimal(v[a], dec) when lossless
      }
    }
    // The tab form closes a row with a tab, as OpenSim writes: its reader drops an empty last
    // field, so a row ending in a gap would otherwise be one field short. The comma form pads
    // every line to the same width instead.
    if (delim == ',')
      pad(&s, 2 + 3 * N, width);
    else
      s += delim;
    s += '\n';
  }
}

}  // namespace trc

void write_trc(const Take& take, const std::string& path, const WriteOptions& opts) {
  refuse_ragged(take, "the TRC writer (a TRC row holds a fixed number of markers)", path);
  const size_t F = take.frames, N = take.points;
  if (take.xyz.size() != F * N * 3 || take.valid.size() != F * N)
    fail(ErrorCode::kInternal, path, "take arrays do not match frames x points");
  const char delim = trc::output_delimiter(take, opts.trc_delimiter, path);
  // Output is created before formatting so an existing file is refused without work.
  AtomicFile out(path, opts.overwrite);
  const size_t width = delim == ',' ? trc::comma_width(take, path) : 0;
  std::string s = trc::header_text(take, path, delim);
  constexpr size_t kRows = 256;  // rows formatted between writes
  for (size_t fr = 0; fr < F; fr += kRows) {
    const size_t n = std::min(kRows, F - fr);
    trc::append_rows(take, fr, n, take.xyz.data() + fr * N * 3, take.valid.data() + fr * N, delim,
                     width, &s);
    out.write(s.data(), s.size());
    s.clear();
  }
  out.write(s.data(), s.size());
  out.commit();
}

}  // namespace capz
