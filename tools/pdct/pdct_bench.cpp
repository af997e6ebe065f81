// pdct experiments (docs/BENCHMARKS.md, "pdct"): the paper's Figure 4 / 6 runs on a point
// sequence, and pdct against the container's plain coder on takes at a max error.
//
//   pdct_bench grid SEQ [--frames N] [--clusters 10,25,40] [--zero 0,0.5] [--bits 8,10,12]
//       transform alone at fixed quantisation: one CSV row per (clusters, zero share, bits)
//   pdct_bench kg SEQ [--frames N] [--clusters 10,25,40] [--kg 0.1,0.5,1] [--zero 0]
//       transform alone with a KG target: rate-distortion rows
//   pdct_bench bound --max-error E[,E2] [--clusters N|auto] TAKE...
//       whole .capz streams (container + bound layer), codec "none" vs "pdct" at each max
//       error (in the take's units); needs the container's compress()
// CSV on stdout: mode,take,frames,points,clusters,zero_share,coef_bits,target,bytes,bpvf,kg,
// max_error,rmse,seconds,detail
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "capz/error.h"
#include "capz/io.h"
#include "capz/metrics.h"
#include "codec/pdct/pdct_encoder.h"
#ifdef CAPZ_PDCT_BENCH_BOUND
#include "capz/codec.h"
#endif

namespace {

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string x;
  while (std::getline(ss, x, ',')) out.push_back(x);
  return out;
}

std::string base_name(const std::string& p) {
  std::string s = p;
  while (!s.empty() && s.back() == '/') s.pop_back();
  const size_t k = s.find_last_of('/');
  return k == std::string::npos ? s : s.substr(k + 1);
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Gap filling for the transform-only modes: hold the last measurement (back-fill leading gaps).
void fill_gaps(capz::Take* t) {
  for (size_t p = 0; p < t->points; ++p) {
    long last = -1;
    for (size_t f = 0; f < t->frames; ++f) {
      if (t->is_valid(f, p)) {
        if (last < 0)
          for (size_t g = 0; g < f; ++g)
            for (int a = 0; a < 3; ++a) t->at(g, p)[a] = t->at(f, p)[a];
        last = static_cast<long>(f);
      } else if (last >= 0) {
        for (int a = 0; a < 3; ++a) t->at(f, p)[a] = t->at(static_cast<size_t>(last), p)[a];
      }
    }
  }
}

void row(const char* mode, const std::string& take, size_t F, size_t P, const std::string& clusters,
         double zero, int bits, double target, size_t bytes, const capz::ErrorStats& s, double secs,
         const std::string& detail) {
  std::printf("%s,%s,%zu,%zu,%s,%.3f,%d,%.6g,%zu,%.4f,%.5f,%.6g,%.6g,%.2f,%s\n", mode, take.c_str(),
              F, P, clusters.c_str(), zero, bits, target, bytes, capz::bpvf(bytes, F, P),
              s.kg_error, s.max_error, s.rmse, secs, detail.c_str());
  std::fflush(stdout);
}

int usage() {
  std::fprintf(
      stderr,
      "usage: pdct_bench grid|kg SEQ [--frames N] [--clusters L] [--zero L] [--bits L] [--kg L]\n"
      "       pdct_bench bound --max-error L [--clusters N|auto] TAKE...\n");
  return 2;
}

// The command line: the mode, the inputs and the lists each option gives (defaults otherwise).
struct Args {
  std::string mode;
  std::vector<std::string> inputs;
  size_t frames = 0;
  std::vector<std::string> clusters = {"10", "25", "40"}, zero = {"0"}, bits = {"12"},
                           kg = {"0.1", "0.5", "1"}, max_err = {"0.1", "1"};
};

// Reads the options after the mode; exits with the usage when an option lacks its value.
Args parse_args(int argc, char** argv) {
  Args r;
  r.mode = argv[1];
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) std::exit(usage());
      return argv[++i];
    };
    if (a == "--frames")
      r.frames = std::stoul(next());
    else if (a == "--clusters")
      r.clusters = split(next());
    else if (a == "--zero")
      r.zero = split(next());
    else if (a == "--bits")
      r.bits = split(next());
    else if (a == "--kg")
      r.kg = split(next());
    else if (a == "--max-error")
      r.max_err = split(next());
    else
      r.inputs.push_back(a);
  }
  return r;
}

// Reads a take, cut to its first `frames` frames when that is fewer (0: all).
capz::Take read_input(const std::string& in, size_t frames) {
  capz::Take t = capz::read_take(in);
  if (frames > 0 && frames < t.frames) {
    t.frames = frames;
    t.xyz.resize(frames * t.points * 3);
    t.valid.resize(frames * t.points);
  }
  return t;
}

// One transform-only row: pdct of the gap-filled positions v at clusters c, zero share z and
// x (coef_bits for grid, the KG target for kg), compared with the take's own positions.
void transform_row(const std::string& mode, const std::string& name, const capz::Take& t,
                   const capz::PositionsView& v, const std::string& c, const std::string& z,
                   const std::string& x) {
  capz::TransformParams p;
  p.clusters = c == "auto" ? -1 : std::stoi(c);
  p.options["zero_share"] = z;
  if (mode == "grid")
    p.options["coef_bits"] = x;
  else
    p.kg_error = std::stod(x);
  std::vector<uint8_t> bytes;
  std::vector<double> rec;
  capz::PdctReport rep;
  const auto t0 = std::chrono::steady_clock::now();
  capz::encode_pdct(v, p, &bytes, &rec, &rep);
  const double secs = seconds_since(t0);
  const auto s = capz::compare(t.frames, t.points, t.xyz.data(), rec.data(), t.valid.data());
  char detail[200];
  std::snprintf(detail, sizeof detail,
                "frames_pts=%zu seed_B=%zu first_B=%zu coef_B=%zu clusters=%zu", rep.frame_points,
                rep.seed_bytes, rep.first_bytes, rep.coef_bytes, rep.clusters);
  row(mode.c_str(), name, t.frames, t.points, c, std::stod(z), mode == "grid" ? std::stoi(x) : 0,
      mode == "kg" ? std::stod(x) : 0, bytes.size(), s, secs, detail);
}

// The grid and kg modes on one take: a row per (clusters, zero share, bits or KG target).
void run_transform(const Args& a, const std::string& name, const capz::Take& t) {
  capz::Take filled = t;
  fill_gaps(&filled);
  const capz::PositionsView v{filled.frames, filled.points, filled.xyz.data(), filled.valid.data()};
  for (const auto& c : a.clusters)
    for (const auto& z : a.zero)
      for (const auto& x : (a.mode == "grid" ? a.bits : a.kg))
        transform_row(a.mode, name, t, v, c, z, x);
}

// The bound mode on one take: codec "none", then "pdct" at each of the clusters, at each max
// error. Returns 2 when the container is not built in (after saying so), else 0.
int run_bound(const Args& a, const std::string& name, const capz::Take& t) {
#ifdef CAPZ_PDCT_BENCH_BOUND
  for (const auto& e : a.max_err)
    for (const std::string codec : {"none", "pdct"})
      for (const auto& c : (codec == "none" ? std::vector<std::string>{"-"} : a.clusters)) {
        capz::CompressOptions o;
        o.max_error = std::stod(e);
        o.codec = codec == "none" ? "" : codec;
        if (codec != "none") o.clusters = c == "auto" ? -1 : std::stoi(c);
        capz::CompressStats st;
        const auto t0 = std::chrono::steady_clock::now();
        const auto bytes = capz::compress(t, o, &st);
        const double secs = seconds_since(t0);
        row((std::string("bound-") + codec).c_str(), name, t.frames, t.points, c, 0, 0, o.max_error,
            st.position_bytes, st.error, secs, "total_B=" + std::to_string(bytes.size()));
      }
  return 0;
#else
  (void)a, (void)name, (void)t;
  std::fprintf(stderr, "pdct_bench: built without the container (bound mode unavailable)\n");
  return 2;
#endif
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) return usage();
  const Args a = parse_args(argc, argv);
  std::printf(
      "mode,take,frames,points,clusters,zero_share,coef_bits,target,bytes,bpvf,kg,max_error,rmse,"
      "seconds,detail\n");
  try {
    for (const std::string& in : a.inputs) {
      const capz::Take t = read_input(in, a.frames);
      const std::string name = base_name(in);
      if (a.mode == "grid" || a.mode == "kg") {
        run_transform(a, name, t);
      } else if (a.mode == "bound") {
        if (const int rc = run_bound(a, name, t)) return rc;
      } else {
        return usage();
      }
    }
  } catch (const capz::Error& e) {
    std::fprintf(stderr, "pdct_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
