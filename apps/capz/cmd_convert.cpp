// capz convert IN OUT: between .c3d, .trc and PCD, PLY and .bin frames (folders or single frame
// files), keeping point order, labels, rate, units and gaps. The output format follows OUT's name
// (see output_format in capz/io.h); a folder's format is --to's, else the input's when it is
// frames, else PCD.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "capz/error.h"
#include "capz/io.h"
#include "capz/stream.h"
#include "capz/tool/file.h"
#include "cli_util.h"
#include "commands.h"

namespace capz_cli {

namespace fs = std::filesystem;

namespace {

// The write options the flags give (*enc_opt: the PCD encoding flag used, if any).
capz::WriteOptions write_options(const po::variables_map& vm, const char** enc_opt) {
  capz::WriteOptions wo;
  wo.overwrite = vm.count("force") > 0;
  wo.c3d_float = vm.count("c3d-float") > 0;
  wo.drop_fields = vm.count("drop-fields") > 0;
  wo.trc_delimiter = trc_delimiter(vm, '\t');
  if (vm.count("pcd-encoding") && vm.count("pcd-data"))
    throw po::error("give --pcd-encoding or --pcd-data, not both");
  *enc_opt = vm.count("pcd-data") ? "pcd-data" : "pcd-encoding";
  if (vm.count(*enc_opt)) {
    const std::string e = vm[*enc_opt].as<std::string>();
    if (e != "ascii" && e != "binary" && e != "binary_compressed")
      capz::fail(capz::ErrorCode::kInvalidParameter, "",
                 "--pcd-encoding must be ascii, binary or binary_compressed, not '" + e + "'");
    wo.pcd_encoding = e;
  }
  if (vm.count("ply-encoding")) {
    const std::string e = vm["ply-encoding"].as<std::string>();
    if (e != "ascii" && e != "binary_little_endian" && e != "binary_big_endian")
      capz::fail(capz::ErrorCode::kInvalidParameter, "",
                 "--ply-encoding must be ascii, binary_little_endian or binary_big_endian, not '" +
                     e + "'");
    wo.ply_encoding = e;
  }
  if (vm.count("to")) {
    const std::string t = vm["to"].as<std::string>();
    wo.folder_format = t == "pcd"   ? capz::Format::kPCDFolder
                       : t == "ply" ? capz::Format::kPLYFolder
                       : t == "bin" ? capz::Format::kBinFolder
                                    : capz::Format::kUnknown;
    if (wo.folder_format == capz::Format::kUnknown)
      capz::fail(capz::ErrorCode::kInvalidParameter, "",
                 "--to must be pcd, ply or bin, not '" + t + "'");
  }
  return wo;
}

bool is_frames(capz::Format f) {
  return f == capz::Format::kPCDFolder || f == capz::Format::kPLYFolder ||
         f == capz::Format::kBinFolder;
}

// The reader's warnings, and what the output format does not keep (at the default verbosity).
void print_notes(const capz::Take& take, const std::string& in, capz::Format out_format) {
  for (const auto& w : take.warnings)
    std::fprintf(stderr, "capz convert: %s: %s\n", in.c_str(), w.c_str());
  for (const std::string& d : capz::dropped_by(take, out_format))
    std::fprintf(stderr, "capz convert: note: %s does not keep %s\n", capz::format_name(out_format),
                 d.c_str());
  if (!is_frames(out_format) && take.rate <= 0)
    std::fprintf(stderr, "capz convert: note: the source has no frame rate; give --rate\n");
}

// convert's options.
po::options_description convert_options() {
  po::options_description opts("convert options");
  opts.add_options()("force,f", "overwrite OUT if it exists")(
      "pcd-encoding", po::value<std::string>(),
      "PCD output: ascii, binary or binary_compressed (default: the source's encoding when it is "
      "a PCD folder, else binary)")("pcd-data", po::value<std::string>(),
                                    "the same as --pcd-encoding")(
      "drop-fields",
      "write a C3D or TRC from PCD frames with point fields (rgb, intensity, normals, ...) by "
      "leaving the fields out; without it that is an error naming them")(
      "c3d-float", "C3D output: store coordinates as float even if the source was int16")(
      "to", po::value<std::string>(),
      "the format of a folder OUT: pcd, ply or bin (default: IN's when it is PCD, PLY or .bin "
      "frames, else pcd)")("ply-encoding", po::value<std::string>(),
                           "PLY output: ascii, binary_little_endian or binary_big_endian "
                           "(default: the source's when it is PLY, else binary_little_endian)")(
      "rate", po::value<double>(), "set the frame rate in Hz (for sources without one, e.g. PCD)")(
      "units", po::value<std::string>(), "set the units (mm, cm, m, ...) when the source has none");
  add_trc_delimiter_option(&opts, "tab");
  add_bin_fields_option(&opts);
  return opts;
}

// The cheap checks, before anything is read: the rate given, OUT's name, an existing OUT and OUT
// the input itself. Returns OUT without trailing slashes.
std::string check_convert_output(const po::variables_map& vm, const std::string& in,
                                 const std::string& out, const capz::WriteOptions& wo) {
  if (vm.count("rate")) {
    double r = vm["rate"].as<double>();
    if (!(r > 0) || !std::isfinite(r))
      capz::fail(capz::ErrorCode::kInvalidParameter, "", "--rate must be a positive number of Hz");
  }
  if (capz::format_for_output(out) == capz::Format::kUnknown)
    capz::fail(capz::ErrorCode::kUsage, out,
               "cannot tell the output format from the name: use .c3d, .trc, .pcd, .ply, .bin, "
               "or a folder path (no extension or ending in '/') for frame files");
  const std::string target = capz::without_trailing_slashes(out);
  capz::check_output_free(target, wo.overwrite, capz::frames_go_beside);
  std::error_code ec;
  if (fs::exists(in, ec) && fs::exists(target, ec) && fs::equivalent(in, target, ec))
    capz::fail(capz::ErrorCode::kUsage, out, "output is the input");
  return target;
}

// What convert says after writing (at the default verbosity): the frames' warnings, the fields
// a C3D or TRC left out, and the line of what was converted.
void print_converted(const capz::FrameSource& src, const capz::Take& take, const std::string& in,
                     const std::string& target, capz::Format out_format) {
  if (g_verbosity < 1) return;
  for (const std::string& w : src.frame_warnings())
    std::fprintf(stderr, "capz convert: %s: %s\n", in.c_str(), w.c_str());
  if (!is_frames(out_format) && !take.attributes.empty())
    std::fprintf(stderr, "capz convert: dropped point fields: %s\n",
                 capz::field_names(take).c_str());
  std::fprintf(stderr, "capz convert: %s (%s) -> %s (%s): %s, %s\n", in.c_str(),
               capz::format_name(take.format), target.c_str(), capz::format_name(out_format),
               shape_text(take).c_str(), human_size(output_size(target)).c_str());
}

}  // namespace

int cmd_convert(const Args& args) {
  const po::options_description opts = convert_options();
  po::options_description positionals;
  positionals.add_options()("input", po::value<std::string>(), "IN")(
      "output", po::value<std::string>(), "OUT");
  po::positional_options_description pos;
  pos.add("input", 1).add("output", 1);
  po::variables_map vm;
  if (!parse_args(
          args,
          "capz convert IN OUT [-f] [--to pcd|ply|bin] [--pcd-encoding E] [--ply-encoding E] "
          "[--c3d-float] [--drop-fields]\n"
          "                    [--trc-delimiter tab|comma]",
          "Converts IN to OUT, each a .c3d, a .trc, a .pcd, .ply or .bin frame, or a folder\n"
          "of such frames (OUT: a path without extension or ending in '/'; its format is\n"
          "--to's, else IN's when IN is frames, else PCD), keeping point order, labels,\n"
          "rate, units and gaps (a gap is an empty field in TRC, a NaN point in PCD, PLY\n"
          "and .bin). The output is written to a temporary name and renamed into place; an\n"
          "existing OUT is never replaced without -f.",
          opts, positionals, pos, &vm))
    return 0;
  if (!vm.count("input") || !vm.count("output")) throw po::error("need IN and OUT");
  const std::string in = vm["input"].as<std::string>();
  const std::string out = vm["output"].as<std::string>();
  const char* enc_opt = nullptr;
  capz::WriteOptions wo = write_options(vm, &enc_opt);
  // Cheap checks first: a bad output name or an existing output fails before reading anything.
  const std::string target = check_convert_output(vm, in, out, wo);

  // Read a block of frames at a time (open_frames: C3D by seeks, TRC rows, frame files one by
  // one) and written as they come (write_frames): memory follows a block, not the take, except
  // where an output needs the whole take (a single frame file, an int16 C3D scaled from the data).
  std::unique_ptr<capz::FrameSource> src = capz::open_frames(in, read_options(vm));
  capz::Take& take = src->edit_header();
  const capz::Format out_format = capz::output_format(take, out, wo);
  if (vm.count("rate")) take.rate = vm["rate"].as<double>();
  if (vm.count("units") && (take.units.empty() || take.units_assumed)) {
    take.units = vm["units"].as<std::string>();
    take.units_assumed = false;
  }
  if (!vm.count(enc_opt) && take.pcd) wo.pcd_encoding = take.pcd->encoding;
  // What the output cannot hold is an error naming it (before anything is written), unless
  // --drop-fields says to leave it out.
  capz::check_fields_fit(take, out_format, target, wo);
  if (g_verbosity >= 1) print_notes(take, in, out_format);
  capz::write_frames(*src, out, wo);
  print_converted(*src, take, in, target, out_format);
  return 0;
}

}  // namespace capz_cli
