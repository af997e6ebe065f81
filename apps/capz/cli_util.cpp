#include "cli_util.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <stdexcept>

#include "capz/codec.h"
#include "capz/error.h"
#include "compress_common.h"

namespace fs = std::filesystem;

namespace capz_cli {

bool parse_args(const Args& args, const std::string& usage, const std::string& description,
                const po::options_description& options, const po::options_description& positionals,
                const po::positional_options_description& pos, po::variables_map* vm) {
  po::options_description common("common options");
  common.add_options()("help,h", "print this help and exit")("quiet,q", "print nothing but errors")(
      "verbose,v", "print more detail");
  po::options_description shown;
  shown.add(options).add(common);
  po::options_description all;
  all.add(shown).add(positionals);
  po::store(po::command_line_parser(args).options(all).positional(pos).run(), *vm);
  if (vm->count("help")) {
    std::cout << "usage: " << usage << "\n\n" << description << "\n\n" << shown << "\n";
    return false;
  }
  po::notify(*vm);
  if (vm->count("quiet")) g_verbosity = 0;
  if (vm->count("verbose")) g_verbosity = 2;
  return true;
}

bool parse_single_input(const Args& args, const std::string& usage, const std::string& description,
                        const po::options_description& options, const std::string& input_name,
                        po::variables_map* vm, std::string* input) {
  po::options_description positionals;
  positionals.add_options()("input", po::value<std::string>(), input_name.c_str());
  po::positional_options_description pos;
  pos.add("input", 1);
  if (!parse_args(args, usage, description, options, positionals, pos, vm)) return false;
  if (!vm->count("input")) throw po::error("missing " + input_name);
  *input = (*vm)["input"].as<std::string>();
  return true;
}

void add_memlimit_option(po::options_description* o) {
  o->add_options()(
      "memlimit", po::value<std::string>(),
      "decode with at most SIZE bytes of samples in memory (K, M, G, T suffixes; 0: no "
      "limit; default 4G, or 1024 bytes per archive byte when more); a stream that needs "
      "more is refused, exit 8");
}

void add_trc_delimiter_option(po::options_description* o, const char* default_text) {
  o->add_options()("trc-delimiter", po::value<std::string>(),
                   (std::string("TRC output: tab (OpenSim's form) or comma (every line padded "
                                "with commas to the same field count); default: ") +
                    default_text)
                       .c_str());
}

void add_bin_fields_option(po::options_description* o) {
  o->add_options()("bin-fields", po::value<std::string>(),
                   "the record of .bin frames other than KITTI's (x y z intensity) or nuScenes' "
                   "(*.pcd.bin: x y z intensity ring): \"x y z NAME[:TYPE] ...\", TYPE one of "
                   "F4 F8 U1 U2 U4 U8 I1 I2 I4 I8 (F4 when none), _ for padding");
}

capz::ReadOptions read_options(const po::variables_map& vm) {
  capz::ReadOptions r;
  if (!vm.count("bin-fields")) return r;
  r.bin_fields = vm["bin-fields"].as<std::string>();
  capz::parse_bin_record(r.bin_fields, "");  // a bad record is a usage error up front
  return r;
}

char trc_delimiter(const po::variables_map& vm, char fallback) {
  if (!vm.count("trc-delimiter")) return fallback;
  const std::string v = vm["trc-delimiter"].as<std::string>();
  if (v == "tab") return '\t';
  if (v == "comma") return ',';
  capz::fail(capz::ErrorCode::kInvalidParameter, "",
             "--trc-delimiter must be tab or comma, not '" + v + "'");
}

uint64_t memlimit(const po::variables_map& vm) {
  if (!vm.count("memlimit")) return capz::kAutoMemoryLimit;
  const std::string v = vm["memlimit"].as<std::string>();
  size_t used = 0;
  unsigned long long n = 0;
  try {
    if (v.empty() || v[0] < '0' || v[0] > '9') throw std::invalid_argument(v);
    n = std::stoull(v, &used);
  } catch (const std::exception&) {
    used = std::string::npos;
  }
  int shift = 0;
  if (used != std::string::npos && used + 1 == v.size()) {
    const std::string units = "KMGT";
    const size_t k =
        units.find(static_cast<char>(std::toupper(static_cast<unsigned char>(v[used]))));
    if (k != std::string::npos) {
      shift = 10 * static_cast<int>(k + 1);
      ++used;
    }
  }
  if (used != v.size() || (shift && n > (~0ULL >> shift)))
    capz::fail(capz::ErrorCode::kInvalidParameter, "",
               "--memlimit wants a size in bytes (e.g. 512M, 8G, 0 for none), not '" + v + "'");
  return static_cast<uint64_t>(n) << shift;
}

std::string strprintf(const char* fmt, ...) {
  va_list ap, ap2;
  va_start(ap, fmt);
  va_copy(ap2, ap);
  const int n = std::vsnprintf(nullptr, 0, fmt, ap);
  va_end(ap);
  std::string s(n > 0 ? static_cast<size_t>(n) : 0, '\0');
  if (n > 0) std::vsnprintf(&s[0], s.size() + 1, fmt, ap2);
  va_end(ap2);
  return s;
}

std::string human_size(uint64_t bytes) {
  if (bytes < 1024) return std::to_string(bytes) + " B";
  const char* units[] = {"KiB", "MiB", "GiB", "TiB"};
  double v = static_cast<double>(bytes);
  int u = -1;
  while (v >= 1024 && u < 3) {
    v /= 1024;
    ++u;
  }
  char buf[32];
  std::snprintf(buf, sizeof buf, v < 10 ? "%.2f %s" : v < 100 ? "%.1f %s" : "%.0f %s", v, units[u]);
  return buf;
}

std::string lower_extension(const fs::path& p) {
  std::string e = p.extension().string();
  for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

namespace {

// A file's size, or the total of the regular files directly inside a directory that `counts`.
template <class Counts>
uint64_t bytes_at(const std::string& path, Counts counts) {
  std::error_code ec;
  if (!fs::is_directory(path, ec)) {
    const uint64_t s = fs::file_size(path, ec);
    return ec ? 0 : s;
  }
  uint64_t total = 0;
  for (fs::directory_iterator it(path, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code e2;
    if (it->is_regular_file(e2) && counts(it->path())) total += it->file_size(e2);
  }
  return total;
}

}  // namespace

uint64_t path_size(const std::string& path) {
  return bytes_at(path, [](const fs::path&) { return true; });
}

uint64_t output_size(const std::string& path) {
  return bytes_at(path, [](const fs::path& p) {
    return p.filename().string()[0] != '.' && lower_extension(p) != ".capz";
  });
}

std::string number(double v) {
  if (std::isnan(v)) return "NaN";
  char buf[400];  // the longest fixed form of a double below 1e21 fits
  const double a = std::fabs(v);
  const auto fmt =
      a != 0 && (a >= 1e21 || a < 1e-12) ? std::chars_format::scientific : std::chars_format::fixed;
  return std::string(buf, std::to_chars(buf, buf + sizeof buf, v, fmt).ptr);
}

double shortest_float32(float f) {
  char buf[32];
  for (int digits = 6; digits <= 9; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, static_cast<double>(f));
    if (std::strtof(buf, nullptr) == f) break;
  }
  return std::strtod(buf, nullptr);
}

std::string events_text(const std::vector<capz::C3DEvent>& events) {
  if (events.empty()) return "none";
  const size_t kShown = 8;
  const size_t shown = g_verbosity >= 2 ? events.size() : std::min(kShown, events.size());
  std::string v = std::to_string(events.size()) + ": ";
  for (size_t i = 0; i < shown; ++i) {
    const capz::C3DEvent& e = events[i];
    // The seconds as the file's float32 gives them (3.05, not 3.049999952316284).
    const float f = static_cast<float>(e.time);
    const double t = static_cast<double>(f) == e.time ? shortest_float32(f) : e.time;
    v += (i ? ", " : "") + (e.context.empty() ? "" : e.context + " ") +
         (e.label.empty() ? "(unnamed)" : e.label) + " " + number(t) + " s";
  }
  if (shown < events.size())
    v += ", ... (" + std::to_string(events.size() - shown) + " more; -v lists all)";
  return v;
}

void events_json(Json* j, const std::vector<capz::C3DEvent>& events) {
  j->key("events");
  j->begin_array();
  for (const capz::C3DEvent& e : events) {
    j->begin_object();
    j->member("label", e.label);
    j->member("context", e.context);
    j->member("time", e.time);
    j->member("description", e.description);
    j->member("subject", e.subject);
    j->member("icon_id", e.icon_id);
    j->member("generic_flag", e.generic_flag);
    j->end_object();
  }
  j->end_array();
}

namespace {

// "2^-17" for the float32 split exponent E = 17 (the grid 2^-E).
std::string split_grid(int e) {
  return e > 0 ? "2^-" + std::to_string(e) : "2^" + std::to_string(-e);
}

}  // namespace

std::string positions_text(const std::string& mode, std::map<int, size_t> split,
                           const std::string& u) {
  const auto take = [&](int key) {
    const size_t k = split.count(key) ? split[key] : 0;
    split.erase(key);
    return k;
  };
  const size_t plain = take(capz::kPlainFloat32WindowsKey), raw = take(capz::kRawWindowsKey);
  size_t n = 0;
  for (const auto& kv : split) n += kv.second;
  const size_t all = n + plain + raw;
  const auto windows = [](size_t k) {
    return std::to_string(k) + (k == 1 ? " window" : " windows");
  };
  // Raw windows (FORMAT.md "Raw windows"): the coordinates' bits through LZMA2.
  const auto with_raw = [&](const std::string& s) {
    if (raw == 0) return s;
    return s + (n + plain ? "; " : ", ") + "raw bits through LZMA2 in " +
           (raw == all ? std::string(all > 1 ? "every window" : "the window") : windows(raw));
  };
  if (split.empty())
    return with_raw(plain && raw ? mode + " in " + windows(plain) + " of " + std::to_string(all)
                                 : mode);
  std::string grids;
  for (const auto& kv : split) {
    grids += (grids.empty() ? "" : ", ") + split_grid(kv.first) + " (" +
             num(std::ldexp(1.0, -kv.first)) + u + ")";
    if (split.size() > 1) grids += " in " + windows(kv.second);
  }
  std::string s = std::string("float32 split on the grid") + (split.size() > 1 ? "s " : " ") +
                  grids + ", exact corrections";
  if (n == all) return s + (split.size() == 1 && n > 1 ? ", every window" : "");
  s += ", in " + windows(n) + " of " + std::to_string(all);
  return with_raw(plain ? s + "; float32-bits in " + windows(plain) : s);
}
std::string shape_text(size_t frames, size_t points, bool ragged, size_t total_points) {
  return ragged ? std::to_string(frames) + " frames of their own point counts, " +
                      std::to_string(total_points) + " points in all"
                : std::to_string(frames) + " frames x " + std::to_string(points) + " points";
}

std::string archive_units(capz::Format source_format, const std::string& stored, bool* assumed) {
  const bool unitless_format = source_format == capz::Format::kPCDFolder ||
                               source_format == capz::Format::kPLYFolder ||
                               source_format == capz::Format::kBinFolder;
  *assumed = stored.empty() && unitless_format;
  return *assumed ? std::string("m") : stored;
}

std::string percent(double share) {
  char buf[32];
  std::snprintf(buf, sizeof buf, share > 0 && share < 0.01 ? "%.2f%%" : "%.1f%%", share * 100);
  return buf;
}

// Length of the valid UTF-8 sequence starting at s[i], or 0 if it is not one.
static size_t utf8_length(const std::string& s, size_t i) {
  const unsigned char c = static_cast<unsigned char>(s[i]);
  size_t n = c >= 0xF0 && c <= 0xF4 ? 4 : c >= 0xE0 ? 3 : c >= 0xC2 && c < 0xE0 ? 2 : 0;
  if (n == 0 || i + n > s.size()) return 0;
  for (size_t k = 1; k < n; ++k)
    if ((static_cast<unsigned char>(s[i + k]) & 0xC0) != 0x80) return 0;
  return n;
}

std::string printable(const std::string& s) {
  std::string o;
  o.reserve(s.size());
  for (size_t i = 0; i < s.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (c >= 0x80) {
      const size_t n = utf8_length(s, i);
      if (n > 0) {
        o.append(s, i, n);
        i += n - 1;
      } else {
        o += static_cast<char>(0xC0 | (c >> 6));
        o += static_cast<char>(0x80 | (c & 0x3F));
      }
    } else {
      o += c < 0x20 || c == 0x7F ? '?' : static_cast<char>(c);
    }
  }
  return o;
}

std::string Json::escape(const std::string& s) {
  std::string o = "\"";
  for (size_t i = 0; i < s.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (c >= 0x80) {
      // Valid UTF-8 passes through; any other byte (Latin-1 labels in old files) is read as
      // Latin-1 and escaped, so the output is always valid JSON.
      size_t n = utf8_length(s, i);
      if (n > 0) {
        o.append(s, i, n);
        i += n - 1;
      } else {
        char buf[8];
        std::snprintf(buf, sizeof buf, "\\u%04x", c);
        o += buf;
      }
      continue;
    }
    switch (c) {
      case '"':
        o += "\\\"";
        break;
      case '\\':
        o += "\\\\";
        break;
      case '\b':
        o += "\\b";
        break;
      case '\f':
        o += "\\f";
        break;
      case '\n':
        o += "\\n";
        break;
      case '\r':
        o += "\\r";
        break;
      case '\t':
        o += "\\t";
        break;
      default:
        if (c < 0x20 || c == 0x7f) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          o += buf;
        } else {
          o += static_cast<char>(c);
        }
    }
  }
  return o + "\"";
}

void Json::separate() {
  if (after_key_) {
    after_key_ = false;
    return;
  }
  if (!first_.empty()) {
    if (!first_.back()) out_ += ',';
    first_.back() = false;
  }
}

void Json::begin_object() {
  separate();
  out_ += '{';
  first_.push_back(true);
}
void Json::end_object() {
  first_.pop_back();
  out_ += '}';
}
void Json::begin_array() {
  separate();
  out_ += '[';
  first_.push_back(true);
}
void Json::end_array() {
  first_.pop_back();
  out_ += ']';
}
void Json::key(const std::string& k) {
  separate();
  out_ += escape(k);
  out_ += ':';
  after_key_ = true;
}
void Json::value(const std::string& s) {
  separate();
  out_ += escape(s);
}
void Json::value(double v) {
  separate();
  out_ += std::isfinite(v) ? number(v) : std::string("null");
}
void Json::value(uint64_t v) {
  separate();
  out_ += std::to_string(v);
}
void Json::value(int64_t v) {
  separate();
  out_ += std::to_string(v);
}
void Json::value(bool b) {
  separate();
  out_ += b ? "true" : "false";
}
void Json::null() {
  separate();
  out_ += "null";
}
void Json::member_strings(const std::string& k, const std::vector<std::string>& v) {
  key(k);
  begin_array();
  for (const auto& s : v) value(s);
  end_array();
}

std::string pcd_fields_text(const std::vector<capz::PCDField>& fields) {
  std::string v;
  for (const capz::PCDField& f : fields) {
    v += (v.empty() ? "" : ", ") + f.name + " " + std::string(1, f.type) + std::to_string(f.size);
    if (f.count != 1) v += "x" + std::to_string(f.count);
  }
  return v;
}

void pcd_fields_json(Json* j, const std::vector<capz::PCDField>& fields) {
  j->key("fields");
  j->begin_array();
  for (const capz::PCDField& f : fields) {
    j->begin_object();
    j->member("name", f.name);
    j->member("type", std::string(1, f.type));
    j->member("size", f.size);
    j->member("count", f.count);
    j->end_object();
  }
  j->end_array();
}

}  // namespace capz_cli
