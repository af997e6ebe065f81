// capz_tsbench: measurements of the ts codec alone (docs/BENCHMARKS.md, ts section).
//
//   capz_tsbench table2 IN --kg X [--kmax 5] [--frames F] [--opt key=value ...]
//       The paper's Table 2: cluster counts 1..kmax at a fixed KG target; per K the PCs per
//       cluster, bytes, bpvf, achieved KG error, and the encoder's time per step (Table 3).
//   capz_tsbench rd IN --kg X1,X2,... [--clusters K|auto] [--frames F] [--opt key=value ...]
//       Rate-distortion points: per KG target the bytes, bpvf, KG and max error achieved.
//
// IN is a PCD folder (or any input capz reads). Every payload is decoded again and checked to
// equal the encoder's reconstruction bit for bit. Output: one markdown table row per run.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "capz/error.h"
#include "capz/io.h"
#include "capz/metrics.h"
#include "codec/ts/ts_encoder.h"

using namespace capz;

namespace {

int usage() {
  std::fprintf(stderr,
               "usage: capz_tsbench table2 IN --kg X [--kmax 5] [--frames F] [--opt k=v ...]\n"
               "       capz_tsbench rd IN --kg X1,X2,... [--clusters K|auto] [--frames F] [--opt "
               "k=v ...]\n");
  return 1;
}

Take load(const std::string& path) {
  try {
    return read_pcd_folder(path);
  } catch (const Error&) {
    return read_take(path);
  }
}

void run(const Take& t, size_t nf, const TransformParams& tp, const char* mode) {
  PositionsView v{nf, t.points, t.xyz.data(), t.valid.data()};
  TsCodec codec;
  TsEncodeReport rep;
  std::vector<uint8_t> bytes;
  std::vector<double> recon, dec;
  codec.encode_report(v, tp, &bytes, &recon, &rep);
  codec.decode(bytes.data(), bytes.size(), nf, t.points, &dec);
  const bool exact = dec.size() == recon.size() &&
                     std::memcmp(dec.data(), recon.data(), dec.size() * sizeof(double)) == 0;
  ErrorStats e = compare(nf, t.points, t.xyz.data(), dec.data(), t.valid.data());
  std::ostringstream pcs;
  int total = 0;
  for (int p : rep.pcs) total += p;
  if (rep.segments > 1) {  // per (segment, cluster) lists get long: the total only
    pcs << "S=" << rep.segments << ": " << total << " PCs";
  } else {
    pcs << "{";
    for (size_t i = 0; i < rep.pcs.size(); ++i) pcs << (i ? ", " : "") << rep.pcs[i];
    pcs << "}";
  }
  const double rate = bpvf(bytes.size(), nf, t.points);
  const double ratio =
      100.0 * static_cast<double>(bytes.size()) / (static_cast<double>(nf * t.points) * 12.0);
  if (std::strcmp(mode, "table2") == 0) {
    std::printf(
        "| %d | %.4f | %s | %d | %zu | %.3f | %.3f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %d "
        "|%s\n",
        rep.clusters, e.kg_error, pcs.str().c_str(), total, bytes.size(), rate, ratio, rep.t_align,
        rep.t_cluster, rep.t_pca, rep.t_quant, rep.t_lcps, rep.t_total, rep.trials,
        exact ? "" : " DECODE MISMATCH");
  } else {
    std::printf("| %.3f | %d %s | %.4f | %.4g | %zu | %.3f | %.2f |%s\n", tp.kg_error, rep.clusters,
                pcs.str().c_str(), e.kg_error, e.max_error, bytes.size(), rate, rep.t_total,
                exact ? "" : " DECODE MISMATCH");
  }
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) return usage();
  const std::string mode = argv[1], in = argv[2];
  if (mode != "table2" && mode != "rd") return usage();
  std::vector<double> kgs;
  int kmax = 5, clusters = -1;
  size_t frames = 0;
  TransformParams base;
  for (int i = 3; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--kg" && i + 1 < argc) {
      std::stringstream ss(argv[++i]);
      std::string item;
      while (std::getline(ss, item, ',')) kgs.push_back(std::atof(item.c_str()));
    } else if (a == "--kmax" && i + 1 < argc) {
      kmax = std::atoi(argv[++i]);
    } else if (a == "--clusters" && i + 1 < argc) {
      const std::string c = argv[++i];
      clusters = c == "auto" ? -1 : std::atoi(c.c_str());
    } else if (a == "--frames" && i + 1 < argc) {
      frames = std::strtoul(argv[++i], nullptr, 10);
    } else if (a == "--opt" && i + 1 < argc) {
      const std::string kv = argv[++i];
      const size_t eq = kv.find('=');
      if (eq == std::string::npos) return usage();
      base.options[kv.substr(0, eq)] = kv.substr(eq + 1);
    } else {
      return usage();
    }
  }
  if (kgs.empty()) return usage();
  try {
    const Take t = load(in);
    const size_t nf = frames ? std::min(frames, t.frames) : t.frames;
    std::printf("%s: %zu frames x %zu points\n", in.c_str(), nf, t.points);
    if (mode == "table2") {
      std::printf(
          "| K | KG (%%) | PCs per cluster | total PCs | bytes | bpvf | size (%% of float32) | "
          "align s | cluster s | PCA s | quantise s | LPC+LCPS s | total s | trials |\n");
      std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
      for (int k = 1; k <= kmax; ++k) {
        TransformParams tp = base;
        tp.kg_error = kgs[0];
        tp.clusters = k;
        run(t, nf, tp, "table2");
      }
    } else {
      std::printf("| KG target (%%) | K {PCs} | KG (%%) | max error | bytes | bpvf | encode s |\n");
      std::printf("|---|---|---|---|---|---|---|\n");
      for (double kg : kgs) {
        TransformParams tp = base;
        tp.kg_error = kg;
        tp.clusters = clusters;
        run(t, nf, tp, "rd");
      }
    }
  } catch (const Error& e) {
    std::fprintf(stderr, "capz_tsbench: %s\n", e.what());
    return 2;
  }
  return 0;
}
