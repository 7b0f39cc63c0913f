// The beam pass in AVX2 lanes (4 doubles): kernels/beam_lanes.hpp compiled for "avx2" (no FMA, so every
// lane operation rounds as in the SSE2 pass and the results are bit-identical). Only the code of
// beam_lanes.hpp, all of it with internal linkage, is compiled for AVX2: the headers it depends on are
// included first, under the build's baseline target, so no inline function shared with other units (Eigen,
// the beam law, the timers) is emitted here with AVX2 instructions. bond_kernels.cpp calls this only when
// the CPU has AVX2.
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "kernels/beam.hpp"
#include "kernels/bond_kernels.hpp"
#include "kernels/densification.hpp"
#include "kernels/parallel.hpp"
#include "kernels/views.hpp"

#pragma GCC push_options
#pragma GCC target("avx2")
#include "kernels/beam_lanes.hpp"

namespace vitrum::detail {

void beamPassAvx2(const BondView& bonds, const ParticleView& particles, const BeamPass& pass) {
    beamPassInLanes<4>(bonds, particles, pass);
}

} // namespace vitrum::detail
#pragma GCC pop_options
