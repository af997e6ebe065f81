#include "batch.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <filesystem>
#include <map>
#include <mutex>
#include <new>
#include <thread>

#include "capz/error.h"
#include "capz/io.h"
#include "capz/tool/file.h"
#include "cli_util.h"

namespace fs = std::filesystem;

namespace capz_cli {

namespace {

// The inputs below `dir` (itself included, for a folder of PCD, PLY or .bin frames), sorted.
void walk(const fs::path& dir, InputKind kind, std::vector<fs::path>* found) {
  if (kind == InputKind::kTakes && capz::holds_frame_files(dir.string())) found->push_back(dir);
  std::vector<fs::path> entries;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    entries.push_back(it->path());
  if (ec) capz::fail(capz::ErrorCode::kIo, dir.string(), "cannot list: " + ec.message());
  std::sort(entries.begin(), entries.end());
  for (const fs::path& p : entries) {
    std::error_code e2;
    if (fs::is_directory(p, e2) && !fs::is_symlink(p, e2)) {
      walk(p, kind, found);
      continue;
    }
    const std::string ext = lower_extension(p);
    // Frame files inside a folder of frames belong to that folder's take.
    const bool wanted = kind == InputKind::kTakes ? ext == ".c3d" || ext == ".trc" : ext == ".capz";
    if (wanted && fs::is_regular_file(p, e2)) found->push_back(p);
  }
}

// The mirror path of `p`: the path as given, without its root ("/") and without the ".."
// at its head ("../data/a.c3d" -> "data/a.c3d", "/x/y.c3d" -> "x/y.c3d").
std::string mirror_path(const std::string& p) {
  const fs::path n = fs::path(capz::without_trailing_slashes(p)).lexically_normal();
  fs::path rel;
  bool head = true;
  for (const fs::path& part : n.relative_path()) {
    if (head && (part == ".." || part == ".")) continue;
    head = false;
    rel /= part;
  }
  return rel.empty() ? n.filename().string() : rel.string();
}

void check_settings(const std::vector<Job>& jobs, const BatchSettings& s) {
  const bool stdin_job =
      std::any_of(jobs.begin(), jobs.end(), [](const Job& j) { return j.from_stdin; });
  if (stdin_job && jobs.size() > 1)
    capz::fail(capz::ErrorCode::kUsage, "", "'-' (stdin) must be the only input");
  if (jobs.size() > 1 && !s.output.empty())
    capz::fail(capz::ErrorCode::kUsage, "",
               "-o takes a single input (" + std::to_string(jobs.size()) +
                   " given): use --output-dir-mirror or --output-dir-flat");
  if (jobs.size() > 1 && s.to_stdout)
    capz::fail(capz::ErrorCode::kUsage, "",
               "-c takes a single input (" + std::to_string(jobs.size()) + " given)");
  if (stdin_job && (!s.mirror_dir.empty() || !s.flat_dir.empty()))
    capz::fail(capz::ErrorCode::kUsage, "",
               "stdin goes to stdout or -o, not to --output-dir-mirror / --output-dir-flat");
}

std::mutex g_claims_mutex;
std::map<std::string, std::string> g_claims;  // output (normalised) -> input

}  // namespace

void add_batch_options(po::options_description* o, bool outputs, const std::string& output_help) {
  if (outputs) {
    o->add_options()("output,o", po::value<std::string>(), output_help.c_str())(
        "stdout,c", "write the output to stdout (a single input)")(
        "output-dir-mirror", po::value<std::string>(),
        "write each output under DIR at its input's path (a/b/x.c3d -> DIR/a/b/x.c3d.capz; "
        "a leading / or ../ is dropped)")(
        "output-dir-flat", po::value<std::string>(),
        "write every output directly in DIR (two inputs of one name: the second fails)");
  }
  o->add_options()("force,f", outputs ? "overwrite existing outputs and --report"
                                      : "overwrite an existing --report file")(
      "recursive,r", "walk folders given as inputs")(
      "threads,T", po::value<unsigned>()->default_value(1),
      "files worked on at once (0: one per core); outputs and lines do not depend on it")(
      "report", po::value<std::string>(),
      "write one JSON line per file to FILE.jsonl at the end (never overwritten without -f)");
}

BatchSettings batch_settings(const po::variables_map& vm, bool outputs) {
  BatchSettings s;
  s.recursive = vm.count("recursive") != 0;
  s.threads = vm["threads"].as<unsigned>();
  if (s.threads == 0) s.threads = std::max(1u, std::thread::hardware_concurrency());
  if (vm.count("report")) s.report = vm["report"].as<std::string>();
  s.force = vm.count("force") != 0;
  if (!outputs) return s;
  s.to_stdout = vm.count("stdout") != 0;
  if (vm.count("output")) s.output = vm["output"].as<std::string>();
  if (vm.count("output-dir-mirror")) s.mirror_dir = vm["output-dir-mirror"].as<std::string>();
  if (vm.count("output-dir-flat")) s.flat_dir = vm["output-dir-flat"].as<std::string>();
  const int places = (s.output.empty() ? 0 : 1) + (s.to_stdout ? 1 : 0) +
                     (s.mirror_dir.empty() ? 0 : 1) + (s.flat_dir.empty() ? 0 : 1);
  if (places > 1)
    throw po::error("give only one of -o, -c, --output-dir-mirror, --output-dir-flat");
  return s;
}

bool parse_inputs(const Args& args, const std::string& usage, const std::string& description,
                  const po::options_description& options, const std::string& input_name,
                  bool stdin_allowed, po::variables_map* vm, std::vector<std::string>* inputs) {
  po::options_description positionals;
  positionals.add_options()("input", po::value<std::vector<std::string>>(), input_name.c_str());
  po::positional_options_description pos;
  pos.add("input", -1);
  if (!parse_args(args, usage, description, options, positionals, pos, vm)) return false;
  if (vm->count("input")) {
    *inputs = (*vm)["input"].as<std::vector<std::string>>();
  } else if (stdin_allowed && !isatty(STDIN_FILENO)) {
    *inputs = {"-"};
  } else {
    throw po::error("missing " + input_name);
  }
  return true;
}

std::vector<Job> expand_inputs(const std::vector<std::string>& args, InputKind kind,
                               const BatchSettings& s) {
  std::vector<Job> jobs;
  for (const std::string& a : args) {
    Job j;
    j.input = a;
    if (a == "-") {
      j.from_stdin = true;
      j.to_stdout = s.output.empty();
      j.output = s.output;
      jobs.push_back(j);
      continue;
    }
    std::error_code ec;
    const bool dir = fs::is_directory(a, ec);
    if (dir && s.recursive) {
      std::vector<fs::path> found;
      walk(a, kind, &found);
      for (const fs::path& p : found) {
        Job f;
        f.input = p == fs::path(a) ? a : p.string();
        f.rel = mirror_path(f.input);
        jobs.push_back(f);
      }
      continue;
    }
    if (dir && kind == InputKind::kArchives)
      j.expand_error = a + ": is a folder (use -r to walk it)";
    j.rel = mirror_path(a);
    j.to_stdout = s.to_stdout;
    j.output = s.output;
    jobs.push_back(j);
  }
  if (jobs.empty())
    capz::fail(capz::ErrorCode::kUsage, "",
               kind == InputKind::kTakes ? "no .c3d, .trc or folder of frames found in the inputs"
                                         : "no .capz found in the inputs");
  check_settings(jobs, s);
  return jobs;
}

std::string place_output(const BatchSettings& s, const Job& job, const std::string& name) {
  fs::path dir;
  if (!s.flat_dir.empty()) {
    dir = s.flat_dir;
  } else if (!s.mirror_dir.empty()) {
    dir = fs::path(s.mirror_dir) / fs::path(job.rel).parent_path();
  } else {
    dir = fs::path(capz::without_trailing_slashes(job.input)).parent_path();
  }
  if (dir.empty()) return name;
  // Those the run makes and leaves empty (a failed output's) are removed at its end.
  if (!s.flat_dir.empty() || !s.mirror_dir.empty()) capz::create_output_folders(dir.string());
  return (dir / name).string();
}

void claim_output(const std::string& out, const std::string& input) {
  const std::string key = fs::path(capz::without_trailing_slashes(out)).lexically_normal().string();
  std::lock_guard<std::mutex> lock(g_claims_mutex);
  auto it = g_claims.find(key);
  if (it != g_claims.end())
    capz::fail(capz::ErrorCode::kUsage, input,
               "its output " + out + " is also the output of " + it->second);
  g_claims[key] = input;
}

namespace {

// Files done of the total and MB/s of input, on one line of stderr (a terminal only).
class BatchProgress {
 public:
  BatchProgress(const std::string& command, size_t total, bool on)
      : command_(command), total_(total), on_(on), t0_(std::chrono::steady_clock::now()) {}
  void clear() {
    if (shown_) std::fprintf(stderr, "\r\033[K");
    shown_ = false;
  }
  void update(size_t done, uint64_t bytes) {
    if (!on_) return;
    const auto now = std::chrono::steady_clock::now();
    if (done < total_ && now - last_ < std::chrono::milliseconds(100)) return;
    last_ = now;
    const double s = std::chrono::duration<double>(now - t0_).count();
    std::fprintf(stderr, "\rcapz %s: %zu / %zu files, %.1f MB, %.1f MB/s", command_.c_str(), done,
                 total_, static_cast<double>(bytes) / 1e6,
                 s > 0 ? static_cast<double>(bytes) / 1e6 / s : 0.0);
    std::fflush(stderr);
    shown_ = true;
  }

 private:
  std::string command_;
  size_t total_;
  bool on_, shown_ = false;
  std::chrono::steady_clock::time_point t0_, last_;
};

// A string member, or null when it is empty.
void member_or_null(Json* j, const std::string& key, const std::string& v) {
  if (v.empty()) {
    j->key(key);
    j->null();
  } else {
    j->member(key, v);
  }
}

std::string report_line(const FileRecord& r) {
  Json j;
  j.begin_object();
  j.member("input", r.input);
  member_or_null(&j, "output", r.output);
  j.member("bytes_in", r.bytes_in);
  j.member("bytes_out", r.bytes_out);
  j.member("ratio", r.ratio);
  j.member("bound", r.bound);
  j.member("lossless", r.lossless);
  j.member("units", r.units);
  j.member("max_error", r.max_error);
  member_or_null(&j, "checksum", r.checksum);
  j.member("seconds", r.seconds);
  j.member("ok", r.ok);
  member_or_null(&j, "error", r.ok ? "" : r.error);
  j.end_object();
  return j.str() + "\n";
}

// Where file_note keeps the lines of this thread's file (null: printed at once).
thread_local std::string* t_notes = nullptr;

// Keeps file_note's lines in `notes` while it lives (`keep`), else lets them print at once.
class NotesKept {
 public:
  NotesKept(bool keep, std::string* notes) : saved_(t_notes) { t_notes = keep ? notes : nullptr; }
  ~NotesKept() { t_notes = saved_; }
  NotesKept(const NotesKept&) = delete;
  NotesKept& operator=(const NotesKept&) = delete;

 private:
  std::string* saved_;
};

// Runs one job, turning its failure into the record; with `keep_notes`, file_note's lines go
// into the record.
FileRecord run_one(const Job& job, const Worker& work, bool keep_notes) {
  const auto t0 = std::chrono::steady_clock::now();
  FileRecord r;
  std::string notes;
  NotesKept kept(keep_notes, &notes);
  try {
    if (!job.expand_error.empty()) throw capz::Error(capz::ErrorCode::kUsage, job.expand_error);
    r = work(job);
  } catch (const capz::Error& e) {
    r.ok = false;
    r.code = static_cast<int>(e.code());
    r.error = e.what();
  } catch (const std::bad_alloc&) {
    r.ok = false;
    r.code = 7;
    r.error = job.input + ": out of memory";
  } catch (const std::exception& e) {
    r.ok = false;
    r.code = 7;
    r.error = job.input + ": internal error: " + e.what();
  }
  if (r.input.empty()) r.input = job.from_stdin ? "-" : job.input;
  if (!r.ok && r.code == 0) r.code = 1;
  r.notes = std::move(notes);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

// The jobs of one batch run by its workers, each file's lines printed in the jobs' order as they
// finish (flush, with m held).
struct BatchRun {
  BatchRun(const std::string& command_, const std::vector<Job>& jobs_, const Worker& work_,
           bool failed_lines_)
      : command(command_),
        jobs(jobs_),
        work(work_),
        failed_lines(failed_lines_),
        data_on_stdout(
            std::any_of(jobs.begin(), jobs.end(), [](const Job& j) { return j.to_stdout; })),
        text_out(data_on_stdout ? stderr : stdout),
        records(jobs.size()),
        finished(jobs.size(), false),
        progress(command, jobs.size(),
                 jobs.size() > 1 && g_verbosity >= 1 && isatty(STDERR_FILENO)) {}

  // Prints the finished records that follow the last one printed (called with m held).
  void flush() {
    progress.clear();
    for (; printed < jobs.size() && finished[printed]; ++printed) {
      const FileRecord& r = records[printed];
      if (!r.notes.empty()) std::fputs(r.notes.c_str(), stderr);
      // As zstd: with the data on stdout the per-file lines need -v.
      if (!r.text.empty() && (!data_on_stdout || g_verbosity >= 2))
        std::fputs(r.text.c_str(), text_out);
      if (!r.ok && failed_lines)
        std::fprintf(stdout, "%s: FAILED: %s\n", r.input.c_str(), printable(r.error).c_str());
      else if (!r.ok)
        std::fprintf(stderr, "capz %s: error: %s\n", command.c_str(), printable(r.error).c_str());
    }
    std::fflush(text_out);
    progress.update(done, bytes_done);
  }

  // A worker: takes the next job until none is left.
  void worker() {
    for (;;) {
      size_t i;
      {
        std::lock_guard<std::mutex> lock(m);
        if (next_job == jobs.size()) return;
        i = next_job++;
      }
      FileRecord r = run_one(jobs[i], work, jobs.size() > 1);
      std::lock_guard<std::mutex> lock(m);
      bytes_done += r.bytes_in;
      ++done;
      records[i] = std::move(r);
      finished[i] = true;
      flush();
    }
  }

  // Every job by `workers` threads (the calling one alone for 1).
  void run(size_t workers) {
    progress.update(0, 0);
    if (workers == 1) {
      worker();
    } else {
      std::vector<std::thread> pool;
      for (size_t k = 0; k < workers; ++k) pool.emplace_back([this] { worker(); });
      for (std::thread& t : pool) t.join();
    }
    progress.clear();
  }

  const std::string& command;
  const std::vector<Job>& jobs;
  const Worker& work;
  const bool failed_lines, data_on_stdout;
  std::FILE* const text_out;
  std::vector<FileRecord> records;
  std::vector<bool> finished;
  size_t next_job = 0, printed = 0, done = 0;
  uint64_t bytes_done = 0;
  std::mutex m;
  BatchProgress progress;
};

// The batch's exit status: the first failed file's code (1 with failed_lines), else 0.
int batch_status(const std::vector<FileRecord>& records, bool failed_lines) {
  for (const FileRecord& r : records)
    if (!r.ok) return failed_lines ? 1 : r.code;
  return 0;
}

}  // namespace

void file_note(const std::string& line) {
  if (t_notes)
    *t_notes += line + "\n";
  else
    std::fprintf(stderr, "%s\n", line.c_str());
}

int run_batch(const std::string& command, const BatchSettings& s, std::vector<Job> jobs,
              const Worker& work, bool failed_lines) {
  if (!s.report.empty()) capz::check_output_free(s.report, s.force);
  const size_t workers = std::min<size_t>(std::max(1u, s.threads), jobs.size());
  for (Job& j : jobs) {
    j.threads = std::max<unsigned>(1, s.threads / static_cast<unsigned>(workers));
    j.alone = workers == 1;
  }
  BatchRun run(command, jobs, work, failed_lines);
  run.run(workers);
  int status = batch_status(run.records, failed_lines);
  if (!s.report.empty()) {
    std::string text;
    for (const FileRecord& r : run.records) text += report_line(r);
    try {
      capz::write_file(s.report, std::vector<uint8_t>(text.begin(), text.end()), s.force);
    } catch (const capz::Error& e) {
      std::fprintf(stderr, "capz %s: error: %s\n", command.c_str(), printable(e.what()).c_str());
      if (status == 0) status = static_cast<int>(e.code());
    }
  }
  capz::remove_empty_output_folders();  // after the report, which may be in one of them
  return status;
}

}  // namespace capz_cli
