// The batch driver shared by compress, decompress, test and list: many inputs, -r, output
// placement (beside the input, --output-dir-mirror, --output-dir-flat, -o, -c), a pool of -T
// workers over the files, the per-file lines printed in input order, a progress line, and
// --report FILE.jsonl. Each command keeps its own per-file logic (a Worker); nothing here codes.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "cli_util.h"

namespace capz_cli {

// What the inputs are: takes (.c3d, .trc, PCD folders) or archives (.capz).
enum class InputKind { kTakes, kArchives };

// The batch options, as given.
struct BatchSettings {
  bool recursive = false;  // -r
  std::string output;      // -o (a single input only)
  std::string mirror_dir;  // --output-dir-mirror
  std::string flat_dir;    // --output-dir-flat
  bool to_stdout = false;  // -c (a single input only)
  bool force = false;      // -f
  unsigned threads = 1;    // -T, 0 resolved to the cores
  std::string report;      // --report FILE.jsonl
};

// One input of the batch.
struct Job {
  std::string input;  // the path ("-" for stdin)
  std::string rel;    // its path under --output-dir-mirror (the path without / or ../)
  bool from_stdin = false;
  bool to_stdout = false;  // write the output to stdout (stdin without -o, or -c)
  std::string output;      // -o, else "" (the worker names it: place_output)
  // The threads this file may use inside the library: -T divided among the files in flight
  // (1 while several files run). This is the one place -T reaches a file; the workers pass
  // it on where the library takes a thread count (see cmd_compress.cpp / cmd_decompress.cpp).
  unsigned threads = 1;
  bool alone = true;         // no other file is coded at the same time (its CPU is the process's)
  std::string expand_error;  // found while expanding the arguments (kUsage), e.g. a folder
                             // given to decompress without -r
};

// What a worker reports for one file (the --report line and what the command prints).
struct FileRecord {
  static constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
  std::string input, output;
  uint64_t bytes_in = 0, bytes_out = 0;
  double ratio = kNone;  // original bytes / archive bytes
  double bound = kNone;  // per-coordinate bound in the data's units (lossless: 0)
  bool lossless = false;
  std::string units;
  double max_error = kNone;  // achieved, per coordinate (compress)
  std::string checksum;      // the original's XXH3-128 the archive records ("" when none)
  std::string text;          // the command's lines for this file (to stdout, or stderr with -c)
  std::string notes;         // its warning and note lines (stderr; file_note), in a batch
  // Filled by the driver.
  bool ok = true;
  int code = 0;  // exit status of the failure
  std::string error;
  double seconds = 0;  // wall time of the file
};

// Registers -r, -T, -f, --report and, when `outputs`, -o, -c, --output-dir-mirror and
// --output-dir-flat (`output_help` describes -o).
void add_batch_options(po::options_description* o, bool outputs, const std::string& output_help);
BatchSettings batch_settings(const po::variables_map& vm, bool outputs);

// parse_args with the positionals "input" (any number, named `input_name` in messages). No
// input while stdin is not a terminal means "-" (stdin); with neither, po::error("missing ...").
bool parse_inputs(const Args& args, const std::string& usage, const std::string& description,
                  const po::options_description& options, const std::string& input_name,
                  bool stdin_allowed, po::variables_map* vm, std::vector<std::string>* inputs);

// The jobs: each argument, folders walked with -r (takes: .c3d and .trc files, and every folder
// holding .pcd files as one sequence; archives: .capz files), in sorted order. Checks the
// settings against them (-o and -c with one input only, '-' alone, no output folder for stdin)
// and throws Error(kUsage) when they do not fit.
std::vector<Job> expand_inputs(const std::vector<std::string>& args, InputKind kind,
                               const BatchSettings& s);

// Where a job's output goes, given `name`, the output's name beside the input (no folder; a
// trailing '/' for a PCD folder is kept): beside the input, under the mirror folder at the
// input's relative path, or in the flat folder. Creates the folders it needs
// (capz::create_output_folders: those still empty at run_batch's end, or at a signal, go).
std::string place_output(const BatchSettings& s, const Job& job, const std::string& name);

// Runs `work` on every job with s.threads workers. A worker throws capz::Error on a failure;
// the batch goes on. Prints each file's text (stdout; with the data on stdout, stderr and only
// with -v) and each failure as one line "capz <command>: error: <message>" on stderr (with
// `failed_lines`, as test and list do: "<input>: FAILED: <message>" on stdout), in input order
// whatever the thread count; shows a progress line on stderr for several files (a terminal
// only, not with -q); writes --report at the end, then removes the output folders place_output
// made that hold nothing (a failed file's). Returns 0, or the exit status of the first failing
// file (with `failed_lines`: 1).
using Worker = std::function<FileRecord(const Job&)>;
int run_batch(const std::string& command, const BatchSettings& s, std::vector<Job> jobs,
              const Worker& work, bool failed_lines = false);

// Prints one warning or note line (no newline) about the file being worked on, on stderr: at
// once for a batch of one file; in a batch of several, kept with the file's record (also when
// the file then fails) and printed before its lines, in input order, so that the lines of files
// coded at once do not mix and the progress line is cleared first.
void file_note(const std::string& line);

// Claims `out` for `input` for the rest of the batch; throws Error(kUsage) when another input
// of the batch already writes there (two takes of the same name into one flat folder).
void claim_output(const std::string& out, const std::string& input);

}  // namespace capz_cli
