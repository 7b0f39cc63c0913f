// The beam pass in AVX-512 lanes (8 doubles): kernels/beam_lanes.hpp compiled for "avx512f". AVX-512F has
// fused multiply-add instructions, but the build is ISO C++ (CMAKE_CXX_EXTENSIONS OFF), where GCC's default
// is -ffp-contract=off, and the pragma below says so again: no multiply and add is ever fused, so every lane
// operation rounds as in the SSE2 and AVX2 passes and the three widths are bit-identical
// (BeamLanes.LaneWidthsAreBitIdentical; `objdump -d` of this unit shows no vfmadd). As in
// bond_kernels_avx2.cpp, the headers beam_lanes.hpp depends on are included first, under the baseline
// target, so that no inline function shared with other units is emitted here with AVX-512 instructions.
// bond_kernels.cpp calls this only when the CPU has AVX-512F.
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "kernels/beam.hpp"
#include "kernels/bond_kernels.hpp"
#include "kernels/densification.hpp"
#include "kernels/parallel.hpp"
#include "kernels/views.hpp"

#pragma GCC push_options
#pragma GCC target("avx512f")
#pragma GCC optimize("fp-contract=off")
#include "kernels/beam_lanes.hpp"

namespace vitrum::detail {

void beamPassAvx512(const BondView& bonds, const ParticleView& particles, const BeamPass& pass) {
    beamPassInLanes<8>(bonds, particles, pass);
}

} // namespace vitrum::detail
#pragma GCC pop_options
