// The spring-slider's check (kernels/densification.hpp, paper §2.2.1, Fig 3), on a number type R: the lane
// passes evaluate it for every bond, SpringSlider::update for the bonds that slip. Part of kernels/laws.inl
// (no include guard on purpose). Stresses GPa, strains dimensionless.

/// Axial stress E (ε − ε_r) of a bond, tension positive.
template <class R>
VITRUM_LAW R sliderStress(R young, R strain, R reference_strain) noexcept {
    return young * (strain - reference_strain);
}
/// Compressive stress at which a bond with slip e_p slips further: σ_μ^d + H e_p.
template <class R>
VITRUM_LAW R sliderYield(double yield_stress, double hardening, R slip) noexcept {
    return yield_stress + hardening * slip;
}
/// f = σ_tr − (σ_μ^d + H e_p) for the axial stress `stress` (tension positive); the bond slips where f > 0
/// and e_p < ε_μ^pmax (sliderSlips).
template <class R>
VITRUM_LAW R sliderExcess(double yield_stress, double hardening, R slip, R stress) noexcept {
    return -stress - sliderYield(yield_stress, hardening, slip);
}
template <class R>
VITRUM_LAW MaskOf<R> sliderSlips(double max_slip, R slip, R excess) noexcept {
    return (excess > 0.0) & (slip < max_slip);
}
