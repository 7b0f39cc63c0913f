#include "kernels/fracture.hpp"

#include "kernels/parallel.hpp"

namespace vitrum {

ReleaseCount applyHydrostaticRelease(const HydrostaticRelease& law, const DamageView& d, const IncidenceView& inc,
                                     const BondBreakView& b, std::int64_t step) {
    ReleaseCount count;
    count.released = parallelReduce("fracture.release", d.n, 0LL, [&](std::size_t p, long long& acc) {
        if (!d.released[p] && law.releases(d.stress + 6 * p)) {
            d.released[p] = 1;
            d.release_step[p] = step;
            ++acc;
        }
    });
    if (count.released == 0) {
        return count;
    }
    count.broken = parallelReduce("fracture.break_bonds", b.n, 0LL, [&](std::size_t k, long long& acc) {
        if (!b.broken[k] && (d.released[b.i[k]] || d.released[b.j[k]])) {
            b.broken[k] = 1;
            ++acc;
        }
    });
    parallelFor("fracture.count", d.n, [&](std::size_t p) {
        std::int32_t broken = 0;
        for (std::int32_t e = inc.offset[p]; e < inc.offset[p + 1]; ++e) {
            broken += b.broken[inc.entry[e] >> 1] ? 1 : 0;
        }
        d.broken_bonds[p] = broken;
    });
    return count;
}

} // namespace vitrum
