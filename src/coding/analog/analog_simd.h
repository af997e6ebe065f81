// Runtime choice of the analog encoder's AVX2 kernels: analog_lpc.cpp's autocorrelation and
// LPC residuals, analog_cross.cpp's residual bit counts. They run when the CPU has AVX2
// (checked once, at run time: the build targets the baseline x86-64 and only these functions
// are compiled for AVX2) unless switched off. Every AVX2 kernel computes the same bits as its
// portable twin: its sums are either exact integers below 2^53 (any order gives them) or added
// in the portable loop's order lane by lane, and target("avx2") does not enable fused
// multiply-add (the analog files are built with -ffp-contract=off besides). The switch
// therefore only moves speed; tests turn it off to compare the two paths.
#pragma once

namespace capz {
namespace analog {

bool avx2_enabled();
void allow_avx2(bool allowed);

}  // namespace analog
}  // namespace capz
