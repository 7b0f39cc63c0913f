// The law functions, on a number type R (kernels/law.hpp). Deliberately without include guard and without
// #include of its own: kernels/law.hpp includes it inside `namespace vitrum::law` for the baseline target, and
// kernels/beam_lanes.hpp once more inside its anonymous namespace after `#pragma GCC target`, so each
// instruction set compiles its own copy of the same source (law.hpp says why). Everything here is a
// VITRUM_LAW template; the types it works on are declared in law.hpp.
#include "kernels/law_ops.inl"
#include "kernels/beam_law.inl"
#include "kernels/slider_law.inl"
