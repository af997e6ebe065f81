// Helpers shared by the capz subcommands: option parsing with the common -h/-q/-v, human-readable
// numbers, and a small JSON writer (hand-written, strings escaped per RFC 8259).
#pragma once

#include <boost/program_options.hpp>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "capz/io.h"
#include "capz/take.h"
#include "commands.h"

namespace capz_cli {

namespace po = boost::program_options;

// Parses `args` against `options` plus the common options (-h/--help, -q/--quiet, -v/--verbose,
// which set g_verbosity), and `positionals` (options named in `pos`, left out of the help: the
// usage line and description document them). On --help prints "usage: <usage>", the
// `description` and every option to stdout and returns false (the command then returns 0).
// Throws po::error on bad options (main() reports it with exit status 1).
bool parse_args(const Args& args, const std::string& usage, const std::string& description,
                const po::options_description& options, const po::options_description& positionals,
                const po::positional_options_description& pos, po::variables_map* vm);

// parse_args for a command with one positional input named `input_name` (e.g. "IN"): sets
// *input, throws po::error("missing IN") when absent; false when --help was printed.
bool parse_single_input(const Args& args, const std::string& usage, const std::string& description,
                        const po::options_description& options, const std::string& input_name,
                        po::variables_map* vm, std::string* input);

// --memlimit SIZE: the decoder's memory limit (capz::DecompressOptions::memory_limit).
void add_memlimit_option(po::options_description* o);
// The limit in bytes from --memlimit (a count of bytes with an optional K, M, G or T suffix, in
// powers of 1024; 0: none), else capz::kAutoMemoryLimit. Throws Error(kInvalidParameter).
uint64_t memlimit(const po::variables_map& vm);

// --trc-delimiter tab|comma: the TRC writer's delimiter (capz::WriteOptions::trc_delimiter).
void add_trc_delimiter_option(po::options_description* o, const char* default_text);
// '\t' for tab, ',' for comma, `fallback` without the option. Throws Error(kInvalidParameter).
char trc_delimiter(const po::variables_map& vm, char fallback);

// --bin-fields "x y z NAME[:TYPE] ...": the record of .bin frames other than KITTI's or nuScenes'
// (capz::ReadOptions::bin_fields).
void add_bin_fields_option(po::options_description* o);
// The read options of --bin-fields (its text checked: Error(kUsage) for a bad record).
capz::ReadOptions read_options(const po::variables_map& vm);

// printf into a std::string.
std::string strprintf(const char* fmt, ...) __attribute__((format(printf, 1, 2)));

// "512 B", "1.5 KiB", "3.20 MiB", "1.07 GiB".
std::string human_size(uint64_t bytes);
// Size of a file, or the total of the regular files directly inside a directory.
uint64_t path_size(const std::string& path);
// A path's extension in lower case (".C3D" -> ".c3d"; "" for none).
std::string lower_extension(const std::filesystem::path& p);
// The bytes a take written to `path` takes: a file's size, or for a folder of frames the total
// of its regular files but the hidden ones and the .capz archives (any case), which the frames
// may have gone in beside (capz::frames_go_beside).
uint64_t output_size(const std::string& path);
// Shortest decimal text that reads back exactly (no exponent for magnitudes in [1e-12, 1e21)).
std::string number(double v);
// The double nearest the shortest decimal that reads back as float32 f: 0.86f gives 0.86, not
// 0.8600000143051147, and parsing either as float32 gives f.
double shortest_float32(float f);
// A take's shape as the commands print it: "450 frames x 26 points", or for frames of their own
// point counts (a ragged take) "4 frames of their own point counts, 7150 points in all".
std::string shape_text(size_t frames, size_t points, bool ragged, size_t total_points);
inline std::string shape_text(const capz::Take& t) {
  return shape_text(t.frames, t.points, t.ragged(), t.total_points());
}
// What `info` and `compress` say of the positions: the mode (CompressStats::mode), or for a
// ragged float32 stream whose windows use a float32 split (FORMAT.md "Lossless ragged streams")
// the grids of the split and how many windows use each, and the windows of plain float32 bits
// (split_windows: StreamInfo::float32_split_windows). u: the units after a number (" m"), or "".
std::string positions_text(const std::string& mode, std::map<int, size_t> split_windows,
                           const std::string& u);
// The units of an archive's take as the commands show them: those it stores, or, for frames of
// a format that carries none (PCD, PLY, .bin) stored without any, metres, as the reader assumed
// when it was compressed (*assumed then true; capz::units_text says so). "" when unknown.
std::string archive_units(capz::Format source_format, const std::string& stored, bool* assumed);
// "3.2%" style share with one decimal (two below 1%).
std::string percent(double share);
// Text from a file (labels, units) made safe for a terminal line: valid UTF-8 passes, any other
// byte above 0x7F is read as Latin-1 (old C3D files write the degree sign as 0xB0) and written
// as UTF-8, and control characters become '?'.
std::string printable(const std::string& s);

// JSON text built incrementally; keys and values are escaped. Usage:
//   Json j; j.begin_object(); j.key("points"); j.value(44); j.end_object(); j.str();
class Json {
 public:
  void begin_object();
  void end_object();
  void begin_array();
  void end_array();
  void key(const std::string& k);
  void value(const std::string& s);
  void value(const char* s) { value(std::string(s)); }
  void value(double v);  // NaN/inf -> null
  void value(uint64_t v);
  void value(int64_t v);
  void value(int v) { value(static_cast<int64_t>(v)); }
  void value(bool b);
  void null();
  // Shorthands for one member.
  template <typename T>
  void member(const std::string& k, const T& v) {
    key(k);
    value(v);
  }
  void member_strings(const std::string& k, const std::vector<std::string>& v);
  const std::string& str() const { return out_; }
  static std::string escape(const std::string& s);  // with the surrounding quotes

 private:
  void separate();
  std::string out_;
  std::vector<bool> first_;  // per open container: no member written yet
  bool after_key_ = false;
};

// capz info's view of a C3D take's EVENT group events (on a .c3d and on its archive): the line's
// text (the count and the first 8 as "Left Foot Strike 3.05 s", all with -v; "none") and the
// --json array "events" (objects label, context, time in seconds as stored, description,
// subject, icon_id, generic_flag).
std::string events_text(const std::vector<capz::C3DEvent>& events);
void events_json(Json* j, const std::vector<capz::C3DEvent>& events);

// PCD fields as `capz info` shows them: "x F4, y F4, ..., fpfh F4x33"; and as a JSON array of
// objects name / type / size / count under key "fields".
std::string pcd_fields_text(const std::vector<capz::PCDField>& fields);
void pcd_fields_json(Json* j, const std::vector<capz::PCDField>& fields);

}  // namespace capz_cli
