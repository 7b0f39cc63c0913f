#include "kernels/fracture.hpp"

#include "kernels/parallel.hpp"

namespace vitrum {

long long releaseParticles(const HydrostaticRelease& law, const DamageView& d, std::int64_t step) {
    return parallelReduce("fracture.release", d.n, 0LL, [&](std::size_t p, long long& acc) {
        if (!d.released[p] && law.releases(d.stress + 6 * p)) {
            d.released[p] = 1;
            d.release_step[p] = step;
            ++acc;
        }
    });
}

long long breakReleasedBonds(const std::uint8_t* released, const BondBreakView& b) {
    return parallelReduce("fracture.break_bonds", b.n, 0LL, [&](std::size_t k, long long& acc) {
        if (!b.broken[k] && (released[b.i[k]] || released[b.j[k]])) {
            b.broken[k] = 1;
            ++acc;
        }
    });
}

void countBrokenBonds(const IncidenceView& inc, const BondBreakView& b, std::int32_t* broken_bonds) {
    parallelFor("fracture.count", inc.n, [&](std::size_t p) {
        std::int32_t broken = 0;
        for (std::int32_t e = inc.offset[p]; e < inc.offset[p + 1]; ++e) {
            broken += b.broken[inc.entry[e] >> 1] ? 1 : 0;
        }
        broken_bonds[p] = broken;
    });
}

ReleaseCount applyHydrostaticRelease(const HydrostaticRelease& law, const DamageView& d, const IncidenceView& inc,
                                     const BondBreakView& b, std::int64_t step) {
    ReleaseCount count;
    count.released = releaseParticles(law, d, step);
    if (count.released == 0) {
        return count;
    }
    count.broken = breakReleasedBonds(d.released, b);
    countBrokenBonds(inc, b, d.broken_bonds);
    return count;
}

} // namespace vitrum
