// The beam pass of one source tree behind a C entry point, compiled with that tree's kernels into a shared
// object (bench/ab/run.py), so that two revisions' passes run in one process on the same data
// (bench/ab/paired.cpp). The entry takes the views of the tree that built the driver: run.py refuses two trees
// whose kernels/views.hpp differ.
#include "kernels/bond_kernels.hpp"
#include "kernels/densification.hpp"

extern "C" __attribute__((visibility("default"))) int vitrum_ab_set_lanes(int width) {
    return vitrum::setBeamLanes(width) ? 1 : 0;
}

/// One beam pass over `b`, `p`: elastic (densified = 0), or with the spring-slider (densified = 1; yield far
/// above every stress, so that every bond stays on the lanes, as BM_BeamLanes/densified:1).
/// densified = 2: not the beam pass but the gather of the bond loads onto the particles (`inc`).
extern "C" __attribute__((visibility("default"))) void vitrum_ab_beam_pass(const vitrum::BondView* b,
                                                                           const vitrum::ParticleView* p,
                                                                           const vitrum::IncidenceView* inc,
                                                                           int densified, double* slip,
                                                                           double* reference_strain) {
    if (densified == 2) {
        vitrum::gatherBondLoads(*inc, *b, *p);
        return;
    }
    if (densified == 0) {
        vitrum::computeBeamLoads(*b, *p);
        return;
    }
    vitrum::DensificationLaw law;
    law.slider.yield_stress = 1e3; // GPa
    vitrum::DensificationView d;
    d.n = b->n;
    d.slip = slip;
    d.reference_strain = reference_strain;
    d.young = const_cast<double*>(b->young);
    d.shear = const_cast<double*>(b->shear);
    d.section_radius = const_cast<double*>(b->section_radius);
    d.axis_i = const_cast<double*>(b->axis_i);
    d.axis_j = const_cast<double*>(b->axis_j);
    d.twist_ref = const_cast<double*>(b->twist_ref);
    vitrum::computeBeamLoads(*b, *p, law, d);
}
