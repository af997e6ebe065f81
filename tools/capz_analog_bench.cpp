// Analog coder benchmark (docs/format-drafts/analog-bench.md): for every C3D take given on the
// command line that has analog channels, the bytes of the analog window codec (in process,
// verified bit for bit) against general and signal codecs run on the same samples:
//   xz -9e, zstd -19 and fpzip of the channel-major float32 samples;
//   flac -8 and wavpack -hhx6 on each channel as 16-bit mono, when every channel is an integer
//   (or a scaled integer) that fits int16.
// Speed is MB/s of raw float32 samples (4 bytes a sample), single thread, best of 3.
//
//   capz_analog_bench [--window ROWS] [--no-peers] [--whole-frames] [--repeats] [--as-stream]
//                     FILE.c3d...
//   capz_analog_bench --per-channel [--window ROWS] [--no-peers] FILE.c3d...
//
// --per-channel prints, per channel, where the bytes go: the kind the codec keeps, the capz
// bytes of the channel coded alone (one-channel windows: no inter-channel reference), reference
// figures in bytes (order-0 empirical entropy of the samples, their first and second
// differences, the LPC residual of choose_lpc per 4096-sample block, and that residual after
// the sign-LMS cascade), and flac -8, wavpack -hhx6 and xz -9e of the channel alone (int16
// when it fits, else xz of its float32 samples).
// --as-stream codes each take as `capz compress` does at the defaults: windows of
// auto_window_frames(points) point frames (1024 to 8192, codec.h) and repeat lists only when the
// encoder's scan asks for them; the figures a user of the CLI gets.
// --whole-frames rounds each window down to whole point frames of the take (at least one);
// --repeats does too and offers repeat lists (FORMAT.md 11.3: channels may name repeated analog
// frames), so the two compare the repeat lists alone. Windows are coded as format 1.0 codes them.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/io.h"
#include "capz/take.h"
#include "codec/grid_choice.h"
#include "coding/analog/analog_cascade.h"
#include "coding/analog/analog_codec.h"
#include "coding/analog/analog_lpc.h"
#include "coding/analog/analog_repeat.h"
#include "coding/entropy.h"

using namespace capz;

namespace {

std::string g_tmp;

void write_file(const std::string& path, const void* data, size_t size) {
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f || std::fwrite(data, 1, size, f) != size) {
    std::perror(path.c_str());
    std::exit(2);
  }
  std::fclose(f);
}

long file_size(const std::string& path) {
  FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return -1;
  std::fseek(f, 0, SEEK_END);
  const long n = std::ftell(f);
  std::fclose(f);
  return n;
}

// Runs `cmd` (which writes `out`, quietly); returns the size of `out`, -1 on failure.
long run_peer(const std::string& cmd, const std::string& out) {
  std::remove(out.c_str());
  if (std::system((cmd + " 2>/dev/null").c_str()) != 0) return -1;
  return file_size(out);
}

struct Result {
  size_t ours = 0;
  double enc_mbs = 0, dec_mbs = 0;
  bool exact = true;
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// repeat_S: the samples per point frame when repeat lists are offered (window a multiple of
// it), else 0.
Result run_ours(const Analog& a, const AnalogHints& h, size_t window, size_t repeat_S) {
  const size_t rows = a.values.size() / a.channels;
  const double mb = 4.0 * static_cast<double>(a.values.size()) / 1e6;
  Result r;
  std::vector<std::vector<uint8_t>> payloads;
  double best_enc = 1e30, best_dec = 1e30;
  for (int rep = 0; rep < 3; ++rep) {
    payloads.clear();
    auto t0 = std::chrono::steady_clock::now();
    for (size_t r0 = 0; r0 < rows; r0 += window) {
      const size_t n = std::min(window, rows - r0);
      payloads.push_back(
          encode_analog_window(&a.values[r0 * a.channels], n, a.channels, h, repeat_S));
    }
    best_enc = std::min(best_enc, seconds_since(t0));
  }
  std::vector<double> back(a.values.size());
  for (int rep = 0; rep < 3; ++rep) {
    auto t0 = std::chrono::steady_clock::now();
    size_t w = 0;
    try {
      for (size_t r0 = 0; r0 < rows; r0 += window, ++w) {
        const size_t n = std::min(window, rows - r0);
        decode_analog_window(payloads[w].data(), payloads[w].size(), n, a.channels,
                             &back[r0 * a.channels], "bench", repeat_S);
      }
    } catch (const Error&) {
      std::fill(back.begin(), back.end(), std::nan(""));  // reported as NOT EXACT
    }
    best_dec = std::min(best_dec, seconds_since(t0));
  }
  for (const auto& p : payloads) r.ours += p.size();
  r.exact = std::memcmp(back.data(), a.values.data(), back.size() * sizeof(double)) == 0;
  r.enc_mbs = mb / best_enc;
  r.dec_mbs = mb / best_dec;
  return r;
}

// Each channel as int16 counts when every sample is an integer or scaled integer within int16;
// empty when some channel is not.
std::vector<std::vector<int16_t>> int16_channels(const Analog& a, const AnalogHints& h) {
  const size_t rows = a.values.size() / a.channels;
  std::vector<std::vector<int16_t>> out;
  for (int c = 0; c < a.channels; ++c) {
    const analog::ChannelHint hint =
        h.channel.size() > static_cast<size_t>(c) ? h.channel[c] : analog::ChannelHint();
    const analog::ChannelRepr r =
        analog::choose_representation(&a.values[c], a.channels, rows, hint);
    std::vector<int16_t> v(rows, 0);
    if (r.kind == analog::Kind::kConst) {
      out.push_back(v);
      continue;
    }
    if (r.kind != analog::Kind::kInt && r.kind != analog::Kind::kScaled) return {};
    for (size_t i = 0; i < rows; ++i) {
      if (r.ints[i] < -32768 || r.ints[i] > 32767) return {};
      v[i] = static_cast<int16_t>(r.ints[i]);
    }
    out.push_back(v);
  }
  return out;
}

struct Peers {
  long xz = -1, zstd = -1, fpzip = -1, flac = -1, wavpack = -1;
};

Peers run_peers(const Analog& a, const AnalogHints& h) {
  Peers p;
  const size_t rows = a.values.size() / a.channels;
  std::vector<float> cm(a.values.size());
  for (int c = 0; c < a.channels; ++c)
    for (size_t i = 0; i < rows; ++i)
      cm[c * rows + i] = static_cast<float>(a.values[i * a.channels + c]);
  const std::string raw = g_tmp + "/f32.raw";
  write_file(raw, cm.data(), cm.size() * 4);
  p.xz = run_peer("xz -9e -T1 -k -c " + raw + " > " + raw + ".xz", raw + ".xz");
  p.zstd = run_peer("zstd -19 -q -f " + raw + " -o " + raw + ".zst", raw + ".zst");
  p.fpzip = run_peer("fpzip -q -t float -2 " + std::to_string(rows) + " " +
                         std::to_string(a.channels) + " -i " + raw + " -o " + raw + ".fpz",
                     raw + ".fpz");
  const auto ch = int16_channels(a, h);
  if (ch.empty()) return p;
  p.flac = p.wavpack = 0;
  for (const auto& v : ch) {
    const std::string pcm = g_tmp + "/ch.raw";
    write_file(pcm, v.data(), v.size() * 2);
    const long f = run_peer(
        "flac -8 -s -f --no-padding --no-seektable --force-raw-format --endian=little "
        "--sign=signed "
        "--channels=1 --bps=16 --sample-rate=1000 -o " +
            pcm + ".flac " + pcm,
        pcm + ".flac");
    const long w = run_peer(
        "wavpack -hhx6 -q -y --raw-pcm=1000,16,1,le " + pcm + " -o " + pcm + ".wv", pcm + ".wv");
    p.flac = (f < 0 || p.flac < 0) ? -1 : p.flac + f;
    p.wavpack = (w < 0 || p.wavpack < 0) ? -1 : p.wavpack + w;
  }
  return p;
}

// Order-0 empirical entropy of v, in bytes.
template <typename T>
double entropy_bytes(const std::vector<T>& v) {
  std::map<T, size_t> h;
  for (T x : v) ++h[x];
  double bits = 0;
  const double n = static_cast<double>(v.size());
  for (const auto& kv : h) bits -= kv.second * std::log2(kv.second / n);
  return bits / 8;
}

// The LPC residual of x as the codec's LPC stage computes it (choose_lpc per 4096-sample
// block; samples before the first are 0).
std::vector<int32_t> lpc_residual(const std::vector<int32_t>& x) {
  const size_t n = x.size(), pad = analog::kMaxLpcOrder;
  std::vector<int32_t> xp(n + pad, 0), r(n);
  std::copy(x.begin(), x.end(), xp.begin() + pad);
  for (size_t b0 = 0; b0 < n; b0 += 4096) {
    const size_t b1 = std::min(n, b0 + 4096);
    const analog::LpcParams p = analog::choose_lpc(x.data() + b0, b1 - b0);
    for (size_t i = b0; i < b1; ++i)
      r[i] = static_cast<int32_t>(x[i] - analog::lpc_predict(p, xp.data() + pad + i));
  }
  return r;
}

// Order-0 empirical entropy, in bytes, of the residuals as the codec splits them: the token
// (bit length and the bit below the top one, coding/entropy.h) plus the raw bits below. Its
// alphabet is small, so unlike entropy_bytes it does not drop towards 0 on short channels
// whose values are mostly distinct.
template <typename T>
double token_entropy_bytes(const std::vector<T>& v) {
  std::vector<int32_t> tok(v.size());
  double raw = 0;
  for (size_t i = 0; i < v.size(); ++i) {
    int extra;
    tok[i] = token_of(zigzag(static_cast<int32_t>(v[i])), &extra);
    raw += extra;
  }
  return entropy_bytes(tok) + raw / 8;
}

const char* kind_name(int k) {
  static const char* names[] = {"const", "int", "scaled", "rank", "f32", "f64", "?", "?"};
  return names[k & 7];
}

// The capz bytes of one channel coded alone in windows of `window` rows, and in *kind the kind
// its first window keeps.
size_t channel_bytes_alone(const std::vector<double>& col, size_t window, const AnalogHints& h1,
                           int* kind) {
  const size_t rows = col.size();
  size_t bytes = 0;
  for (size_t r0 = 0; r0 < rows; r0 += window) {
    const size_t n = std::min(window, rows - r0);
    const std::vector<uint8_t> w = encode_analog_window(col.data() + r0, n, 1, h1, 0);
    bytes += w.size();
    if (*kind < 0) {
      size_t k = 1;  // version byte, then the header size (varint), then the kind byte
      while (w[k] & 0x80) ++k;
      *kind = w[k + 1] & 7;
    }
  }
  return bytes;
}

// A channel's reference figures in bytes (-1 when it is no integer kind), and whether its
// integers fit int16.
struct ChannelFigures {
  double hx = -1, hd1 = -1, hd2 = -1, hlpc = -1, hlms = -1, htok = -1;
  bool fits16 = false;
};

// The order-0 entropies of an integer channel's samples, differences, LPC residual and
// sign-LMS residual, and the least token entropy among them.
ChannelFigures channel_figures(const analog::ChannelRepr& r, size_t rows) {
  ChannelFigures g;
  if (!analog::is_integer_kind(r.kind)) return g;
  const std::vector<int32_t>& x = r.ints;
  std::vector<int32_t> d1(rows), d2(rows);
  g.fits16 = true;
  for (size_t i = 0; i < rows; ++i) {
    d1[i] = x[i] - (i ? x[i - 1] : 0);
    d2[i] = d1[i] - (i ? d1[i - 1] : 0);
    g.fits16 &= x[i] >= -32768 && x[i] <= 32767;
  }
  g.hx = entropy_bytes(x);
  g.hd1 = entropy_bytes(d1);
  g.hd2 = entropy_bytes(d2);
  const std::vector<int32_t> lr = lpc_residual(x);
  g.hlpc = entropy_bytes(lr);
  std::vector<int64_t> lms(rows);
  analog::sign_lms_run(lr.data(), rows, lms.data());
  g.hlms = entropy_bytes(lms);
  g.htok = std::min({token_entropy_bytes(x), token_entropy_bytes(d1), token_entropy_bytes(d2),
                     token_entropy_bytes(lr), token_entropy_bytes(lms)});
  return g;
}

// The peers' bytes on one channel alone (-1 when not run).
struct ChannelPeers {
  long flac = -1, wv = -1, xz = -1;
};

// flac -8 and wavpack of the channel as int16 when it fits, and xz -9e of it (int16, else its
// float32 samples).
ChannelPeers channel_peers(const analog::ChannelRepr& r, const std::vector<double>& col,
                           bool fits16) {
  ChannelPeers p;
  const std::string pcm = g_tmp + "/ch.raw";
  if (fits16) {
    std::vector<int16_t> v(r.ints.begin(), r.ints.end());
    write_file(pcm, v.data(), v.size() * 2);
    p.flac = run_peer(
        "flac -8 -s -f --no-padding --no-seektable --force-raw-format --endian=little "
        "--sign=signed --channels=1 --bps=16 --sample-rate=1000 -o " +
            pcm + ".flac " + pcm,
        pcm + ".flac");
    p.wv = run_peer("wavpack -hhx6 -q -y --raw-pcm=1000,16,1,le " + pcm + " -o " + pcm + ".wv",
                    pcm + ".wv");
  } else {
    std::vector<float> v(col.begin(), col.end());
    write_file(pcm, v.data(), v.size() * 4);
  }
  p.xz = run_peer("xz -9e -T1 -k -c " + pcm + " > " + pcm + ".xz", pcm + ".xz");
  return p;
}

// One line per channel (see the file comment); returns the summed one-channel capz bytes.
size_t per_channel(const std::string& name, const Take& t, const AnalogHints& h, size_t window,
                   bool peers) {
  const Analog& a = t.analog;
  const size_t rows = a.values.size() / a.channels;
  size_t total = 0;
  for (int c = 0; c < a.channels; ++c) {
    std::vector<double> col(rows);
    for (size_t i = 0; i < rows; ++i) col[i] = a.values[i * a.channels + c];
    AnalogHints h1;
    if (static_cast<size_t>(c) < h.channel.size()) h1.channel.push_back(h.channel[c]);
    int kind = -1;
    const size_t bytes = channel_bytes_alone(col, window, h1, &kind);
    total += bytes;
    const analog::ChannelRepr r = analog::choose_representation(
        col.data(), 1, rows, h1.channel.empty() ? analog::ChannelHint() : h1.channel[0]);
    const ChannelFigures g = channel_figures(r, rows);
    const ChannelPeers p = peers ? channel_peers(r, col, g.fits16) : ChannelPeers();
    std::string label = static_cast<size_t>(c) < a.labels.size() ? a.labels[c] : "";
    if (label.empty()) label = "-";
    std::replace(label.begin(), label.end(), ' ', '_');  // one field
    std::printf(
        "CH %-40s %3d %-12.12s %-6s %8zu %9.0f %9.0f %9.0f %9.0f %9.0f %9.0f %8ld %8ld %8ld\n",
        name.c_str(), c, label.c_str(), kind < 0 ? "-" : kind_name(kind), bytes, g.hx, g.hd1, g.hd2,
        g.hlpc, g.hlms, g.htok, p.flac, p.wv, p.xz);
  }
  return total;
}

// The command line: the window and modes, and the files.
struct Options {
  size_t window = 8192;
  bool peers = true, repeats = false, whole_frames = false, channels = false, as_stream = false;
  std::vector<std::string> files;
};

// Reads the options and the files from the command line.
Options parse_options(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--window") && i + 1 < argc)
      o.window = std::strtoul(argv[++i], nullptr, 10);
    else if (!std::strcmp(argv[i], "--no-peers"))
      o.peers = false;
    else if (!std::strcmp(argv[i], "--repeats"))
      o.repeats = o.whole_frames = true;
    else if (!std::strcmp(argv[i], "--per-channel"))
      o.channels = true;
    else if (!std::strcmp(argv[i], "--whole-frames"))
      o.whole_frames = true;
    else if (!std::strcmp(argv[i], "--as-stream"))
      o.as_stream = true;
    else
      o.files.push_back(argv[i]);
  }
  return o;
}

// The --per-channel report of one take: the column heads before the first take, a line per
// channel, then the take's summed one-channel bytes.
void per_channel_take(const std::string& path, const Take& t, const AnalogHints& h,
                      const Options& o, size_t* n_takes) {
  const std::string name = path.size() > 40 ? path.substr(path.size() - 40) : path;
  if ((*n_takes)++ == 0)
    std::printf("CH %-40s %3s %-12s %-6s %8s %9s %9s %9s %9s %9s %9s %8s %8s %8s\n", "take", "c",
                "label", "kind", "capz1", "H0(x)", "H0(d1)", "H0(d2)", "H0(lpc)", "H0(lms)", "Htok",
                "flac-8", "wavpack", "xz-9e");
  const size_t alone = per_channel(name, t, h, o.window, o.peers);
  std::printf("TAKE %s channels alone %zu\n", name.c_str(), alone);
}

// The window rows for a take, and in *rep_S the samples per frame when repeat lists are offered
// (0 when not).
size_t window_rows(const Take& t, const Options& o, size_t* rep_S) {
  const size_t S = static_cast<size_t>(std::max(t.analog.samples_per_frame, 1));
  size_t rows = o.whole_frames ? std::max(S, o.window / S * S) : o.window;
  *rep_S = o.repeats ? S : 0;
  if (o.as_stream) {
    // As `capz compress` codes the take: windows of auto_window_frames(points) point frames,
    // repeat lists when the encoder's scan asks for them (a channel with varying repeated
    // frames in 10% of the take's frames, grid_choice.cpp analog_repeats_worth).
    rows = auto_window_frames(t.points) * S;
    const size_t C = static_cast<size_t>(t.analog.channels),
                 frames = t.analog.values.size() / C / S;
    TakeScan scan;  // its analog counts, as the encoder's scan makes them (over the whole take)
    for (size_t c = 0; c < C; ++c)
      scan.analog_repeats.push_back(
          analog::count_varying_repeats(t.analog.values.data() + c, C, frames, S));
    *rep_S = analog_repeats_worth(scan, frames) ? S : 0;
  }
  return rows;
}

// The sums over the takes of the summary line.
struct Totals {
  size_t ours = 0, raw = 0, miss = 0, takes = 0;
  double enc_s = 0, dec_s = 0;
};

// One take's line: capz's analog bytes against the peers' (when run), added to the totals.
void bench_take(const std::string& path, const Take& t, const AnalogHints& h, const Options& o,
                Totals* tot) {
  size_t rep_S = 0;
  const size_t rows = window_rows(t, o, &rep_S);
  const Result r = run_ours(t.analog, h, rows, rep_S);
  const Peers p = o.peers ? run_peers(t.analog, h) : Peers();
  long best = -1;
  for (long v : {p.xz, p.zstd, p.fpzip, p.flac, p.wavpack})
    if (v > 0 && (best < 0 || v < best)) best = v;
  const double ratio = best > 0 ? static_cast<double>(r.ours) / best : 0;
  const size_t raw = t.analog.values.size() * 4;
  tot->ours += r.ours;
  tot->raw += raw;
  tot->enc_s += raw / 1e6 / r.enc_mbs;
  tot->dec_s += raw / 1e6 / r.dec_mbs;
  ++tot->takes;
  tot->miss += ratio > 0.85;
  std::string name = path.size() > 48 ? path.substr(path.size() - 48) : path;
  std::printf("%-48s %5d %7zu %9zu %9zu %9ld %9ld %9ld %9ld %9ld %7.3f %7.1f %7.1f%s\n",
              name.c_str(), t.analog.channels, t.analog.values.size() / t.analog.channels, raw,
              r.ours, p.xz, p.zstd, p.fpzip, p.flac, p.wavpack, ratio, r.enc_mbs, r.dec_mbs,
              r.exact ? "" : "  NOT EXACT");
  std::fflush(stdout);
  if (!r.exact) tot->miss += 1000;
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse_options(argc, argv);
  char tmpl[] = "/tmp/capz_analog_bench.XXXXXX";
  if (!mkdtemp(tmpl)) return 2;
  g_tmp = tmpl;
  std::printf("%-48s %5s %7s %9s %9s %9s %9s %9s %9s %7s %7s %7s %s\n", "take", "ch", "rows",
              "raw_f32", "capz", "xz-9e", "zstd-19", "fpzip", "flac-8", "wavpack", "ratio", "enc",
              "dec");
  Totals tot;
  for (const std::string& path : o.files) {
    Take t;
    try {
      t = read_take(path);
    } catch (const Error&) {
      continue;
    }
    if (t.analog.channels == 0 || t.analog.values.empty()) continue;
    const AnalogHints h = analog_hints(t);
    if (o.channels)
      per_channel_take(path, t, h, o, &tot.takes);
    else
      bench_take(path, t, h, o, &tot);
  }
  std::printf(
      "takes %zu, raw %zu, capz %zu (%.3f), above 0.85x best peer: %zu; overall encode %.1f MB/s, "
      "decode %.1f MB/s\n",
      tot.takes, tot.raw, tot.ours, static_cast<double>(tot.ours) / tot.raw, tot.miss,
      tot.raw / 1e6 / tot.enc_s, tot.raw / 1e6 / tot.dec_s);
  std::string rm = "rm -rf " + g_tmp;
  if (std::system(rm.c_str()) != 0) return 2;
  return 0;
}
