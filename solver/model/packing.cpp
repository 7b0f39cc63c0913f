#include "solver/model/packing.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <sstream>
#include <stdexcept>

#include "kernels/parallel.hpp"
#include "solver/errors.hpp"
#include "solver/model/bonds.hpp"
#include "solver/model/cell_grid.hpp"
#include "solver/model/particles.hpp"

namespace vitrum {

namespace {

constexpr double kPi = std::numbers::pi;

/// Radius of the largest ball inside the shape, µm.
double inscribedRadius(const PackingParams& p) {
    switch (p.shape) {
    case SampleShape::Box:
        return 0.5 * p.size.minCoeff();
    case SampleShape::Cylinder:
        return std::min(p.radius, 0.5 * p.height);
    case SampleShape::Sphere:
        return p.radius;
    case SampleShape::Hemisphere:
        return 0.5 * p.radius;
    }
    return 0.0;
}

/// The keys that set the shape's dimensions and their values, for messages: "size = [x, y, z] um", ...
std::string shapeKeys(const PackingParams& p) {
    char buf[160] = "";
    switch (p.shape) {
    case SampleShape::Box:
        std::snprintf(buf, sizeof buf, "size = [%.6g, %.6g, %.6g] um", p.size.x(), p.size.y(), p.size.z());
        break;
    case SampleShape::Cylinder:
        std::snprintf(buf, sizeof buf, "radius = %.6g um, height = %.6g um", p.radius, p.height);
        break;
    case SampleShape::Sphere:
    case SampleShape::Hemisphere:
        std::snprintf(buf, sizeof buf, "radius = %.6g um", p.radius);
        break;
    }
    return buf;
}

/// Bounding box of the shape.
void shapeBounds(const PackingParams& p, Vec3& lo, Vec3& hi) {
    switch (p.shape) {
    case SampleShape::Box:
        lo = Vec3::Zero();
        hi = p.size;
        return;
    case SampleShape::Cylinder:
        lo = Vec3(-p.radius, -p.radius, 0.0);
        hi = Vec3(p.radius, p.radius, p.height);
        return;
    case SampleShape::Sphere:
        lo = Vec3::Constant(-p.radius);
        hi = Vec3::Constant(p.radius);
        return;
    case SampleShape::Hemisphere:
        lo = Vec3::Constant(-p.radius);
        hi = Vec3(p.radius, p.radius, 0.0);
        return;
    }
}

/// The faces of the shape as repulsive walls: each face w pushes a sphere of radius r whose centre is closer
/// than r to it along the face's inward normal with force δ_w = r − distance (harmonic, unit stiffness).
struct Walls {
    SampleShape kind = SampleShape::Box;
    Vec3 size = Vec3::Zero();
    double radius = 0.0;
    double height = 0.0;

    /// Adds the wall forces on a sphere (x, r) to f; returns the largest relative wall overlap δ_w / r.
    double push(const Vec3& x, double r, Vec3& f) const {
        double worst = 0.0;
        auto face = [&](double distance, const Vec3& inward) {
            const double overlap = r - distance;
            if (overlap > 0.0) {
                f += overlap * inward;
                worst = std::max(worst, overlap / r);
            }
        };
        switch (kind) {
        case SampleShape::Box:
            face(x.x(), Vec3(1, 0, 0));
            face(size.x() - x.x(), Vec3(-1, 0, 0));
            face(x.y(), Vec3(0, 1, 0));
            face(size.y() - x.y(), Vec3(0, -1, 0));
            face(x.z(), Vec3(0, 0, 1));
            face(size.z() - x.z(), Vec3(0, 0, -1));
            break;
        case SampleShape::Cylinder: {
            const double rho = std::hypot(x.x(), x.y());
            if (rho > 0.0) { // at rho = 0 the side is `radius` ≥ r away (validated)
                face(radius - rho, Vec3(-x.x() / rho, -x.y() / rho, 0.0));
            }
            face(x.z(), Vec3(0, 0, 1));
            face(height - x.z(), Vec3(0, 0, -1));
            break;
        }
        case SampleShape::Sphere:
        case SampleShape::Hemisphere: {
            const double norm = x.norm();
            if (norm > 0.0) {
                face(radius - norm, -x / norm);
            }
            if (kind == SampleShape::Hemisphere) {
                face(-x.z(), Vec3(0, 0, -1));
            }
            break;
        }
        }
        return worst;
    }
};

/// A unit vector that depends only on the unordered pair {a, b}: the push direction of two exactly
/// coincident centres (practically never used, but it keeps the minimiser free of NaN).
Vec3 pairDirection(std::int64_t a, std::int64_t b) {
    std::uint64_t h = static_cast<std::uint64_t>(std::min(a, b)) * 0x9E3779B97F4A7C15ULL ^
                      static_cast<std::uint64_t>(std::max(a, b)) * 0xC2B2AE3D27D4EB4FULL;
    auto next = [&h]() { // splitmix64
        h += 0x9E3779B97F4A7C15ULL;
        std::uint64_t z = h;
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
        return static_cast<double>((z ^ (z >> 31)) >> 11) * 0x1.0p-53 * 2.0 - 1.0;
    };
    Vec3 u(next(), next(), next() + 2.0); // never zero
    u.normalize();
    return a < b ? u : Vec3(-u);
}

/// Fraction of a sphere's volume on the positive side of a plane at signed distance t·r from its centre.
double capFraction(double t) {
    if (t >= 1.0) {
        return 1.0;
    }
    if (t <= -1.0) {
        return 0.0;
    }
    return 1.0 - (1.0 - t) * (1.0 - t) * (2.0 + t) / 4.0;
}

double sphereVolume(double r) {
    return 4.0 / 3.0 * kPi * r * r * r;
}

// Small problems run their loops on the calling thread: a sweep of a few thousand particles takes tens of
// microseconds, less than the fork/join barriers cost when the cores are shared with other work. Below the
// threshold the loops do exactly what the threaded path does on one thread (same chunks, same order of
// partial sums), so results do not depend on which path ran or on the thread count. The packer keeps its own
// order (chunk partials added in chunk order, not parallelReduce's tree): it runs before any decomposition,
// and its packings, cached in sample files, stay the same bits as before the tree.
constexpr std::size_t kPackChunk = 2048; // the packer's own chunk (kReduceChunk was 2048 when its packings were made)
constexpr std::size_t kParallelFrom = 2 * kPackChunk;

template <class T, class Contribution>
T reduceOver(const char* label, std::size_t n, const T& zero, Contribution&& contribution) {
    T total = zero;
    if (n >= kParallelFrom) {
        const std::vector<std::size_t> bounds = uniformChunks(n, kPackChunk);
        for (const T& partial : chunkPartials(label, bounds, zero, contribution)) {
            total += partial;
        }
        return total;
    }
    ScopedTimer timer(label);
    for (std::size_t begin = 0; begin < n; begin += kPackChunk) {
        T acc = zero;
        const std::size_t end = std::min(n, begin + kPackChunk);
        for (std::size_t i = begin; i < end; ++i) {
            contribution(i, acc);
        }
        total += acc;
    }
    return total;
}

/// Sum (+=) of chunk partials for the minimiser's global quantities; max for the maxima (exact in any order).
struct SweepSums {
    double power = 0.0;       ///< F·v
    double force_sq = 0.0;    ///< |F|²
    double velocity_sq = 0.0; ///< |v|²
    double energy = 0.0;      ///< ½ Σ δ² (pairs counted once, walls once)
    double max_overlap = 0.0; ///< relative, pairs and walls
    SweepSums& operator+=(const SweepSums& o) {
        power += o.power;
        force_sq += o.force_sq;
        velocity_sq += o.velocity_sq;
        energy += o.energy;
        max_overlap = std::max(max_overlap, o.max_overlap);
        return *this;
    }
};

struct MaxOf {
    double value = 0.0;
    MaxOf& operator+=(const MaxOf& o) {
        value = std::max(value, o.value);
        return *this;
    }
};

struct SumOf {
    double value = 0.0;
    SumOf& operator+=(const SumOf& o) {
        value += o.value;
        return *this;
    }
};

std::vector<double> flatten(const std::vector<Vec3>& points) {
    std::vector<double> out(3 * points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        store3(out.data(), i, points[i]);
    }
    return out;
}

/// Calls visit(i, j, g) for every pair i < j with normalised gap g = d/(R_i + R_j) − 1 below `gap_cap`, in
/// ascending (i, j) order of i and a fixed order of j. Serial.
template <class Visit>
void forEachClosePair(const std::vector<Vec3>& centres, const std::vector<double>& radii, double gap_cap,
                      Visit&& visit) {
    const std::size_t n = centres.size();
    if (n < 2) {
        return;
    }
    const double r_max = *std::max_element(radii.begin(), radii.end());
    const std::vector<double> flat = flatten(centres);
    CellGrid grid;
    grid.setupAround(flat.data(), n, std::max(2.0 * r_max * (1.0 + gap_cap), 1e-300));
    grid.bin(flat.data(), n);
    grid.forEachPair(flat.data(), n, [&](std::size_t i, std::int32_t j, double d2) {
        const double sum = radii[i] + radii[static_cast<std::size_t>(j)];
        const double reach = (1.0 + gap_cap) * sum;
        if (d2 < reach * reach) {
            visit(static_cast<std::int32_t>(i), j, std::sqrt(d2) / sum - 1.0);
        }
    });
}

/// Region packing fraction over interleaved centres (see regionPackingFraction).
double regionFraction(const SampleParams& shape, double margin, double region_volume, const double* x,
                      const double* r, std::size_t n) {
    if (!(region_volume > 0.0)) {
        return 0.0;
    }
    const SumOf sum = reduceOver("pack.phi", n, SumOf{}, [&](std::size_t i, SumOf& acc) {
        const double h = distanceToBoundary(shape, load3(x, i)) - margin;
        acc.value += capFraction(h / r[i]) * sphereVolume(r[i]);
    });
    return sum.value / region_volume;
}

/// The FIRE minimiser with radius control (steps 2–3 of the algorithm in packing.hpp).
class Compactor {
public:
    Compactor(const PackingParams& params, std::vector<double> x, std::vector<double> r)
        : params_(params), shape_(shapeParams(params)), n_(r.size()), x_(std::move(x)), r_(std::move(r)) {
        walls_.kind = params.shape;
        walls_.size = params.size;
        walls_.radius = params.radius;
        walls_.height = params.height;
        v_.assign(3 * n_, 0.0);
        f_.assign(3 * n_, 0.0);
        shapeBounds(params, box_lo_, box_hi_);
        double sum = 0.0;
        for (double ri : r_) {
            sum += ri;
        }
        mean_radius_ = sum / static_cast<double>(n_);
        // Target region: the interior at 2 R̄ from the walls, unless it is a small part of the shape (very
        // thin shapes, a few hundred particles), where its φ would be mostly noise; then the whole shape,
        // whose loose wall layers need a lower target (failureText says so).
        const double volume = shapeVolume(shape_);
        margin_ = 2.0 * mean_radius_;
        region_volume_ = interiorVolume(shape_, margin_);
        if (region_volume_ < kMinInteriorShare * volume) {
            margin_ = 0.0;
            region_volume_ = volume;
            target_region_ = "whole";
        }
        skin_ = 0.25 * mean_radius_;
        max_step_ = 0.1 * mean_radius_;
    }

    void run() {
        const double target = params_.target_packing_fraction;
        const double floor = target - params_.packing_fraction_tolerance;
        const double tol = params_.overlap_tolerance;
        constexpr long kWindow = 100;          // sweeps between stall checks
        constexpr double kStallRatio = 0.8;    // the energy must fall below this fraction over a window
        constexpr long kPatienceAtTarget = 10; // stalled windows at the target before settling lower
        constexpr long kPatienceAtFloor = 40;  // stalled windows at the floor before giving up
        resetFire();
        buildNeighbours();
        double lowest = target; // where the packer may settle; lowered to `floor` when jammed at the target
        double window_energy = std::numeric_limits<double>::infinity();
        long stalled = 0;
        for (long sweep = 0;; ++sweep) {
            if (sweep >= params_.max_iterations) {
                throw RuntimeFailure(failureText("the sweep cap max_iterations = " +
                                                 std::to_string(params_.max_iterations) + " was reached"));
            }
            iterations_ = sweep + 1;
            const SweepSums sums = computeForces();
            last_ = sums;
            if (sums.max_overlap < tol) {
                const double phi = regionPhi();
                if (phi >= lowest * (1.0 - 1e-4)) {
                    if (phi > target) {
                        scaleToTarget(phi);
                    }
                    return;
                }
                scaleRadii(std::cbrt(lowest / phi)); // below (the walls took less room than guessed): grow
                window_energy = std::numeric_limits<double>::infinity();
                continue;
            }
            if (sweep == 0 || sweep % kWindow != 0) {
                fireStep(sums);
                continue;
            }
            const bool slow = sums.energy > kStallRatio * window_energy;
            window_energy = sums.energy;
            if (!slow) {
                stalled = 0;
                fireStep(sums);
                continue;
            }
            const double phi = regionPhi();
            if (phi > lowest * (1.0 + 1e-4)) {
                // Jammed above where we may settle: shrink (Lubachevsky–Stillinger in reverse), by about half
                // the worst overlap, in finer steps once below the target so as to stop near the densest
                // overlap-free state.
                const double most = phi > target ? 2e-3 : 5e-4;
                const double step = std::clamp(0.5 * sums.max_overlap, 1e-4, most);
                scaleRadii(std::max(1.0 - step, std::cbrt(lowest / phi)));
                window_energy = std::numeric_limits<double>::infinity();
                stalled = 0;
                continue;
            }
            ++stalled;
            if (lowest > floor && stalled >= kPatienceAtTarget) {
                lowest = floor; // jammed at the target (small, wall-dominated samples): settle a little lower
                stalled = 0;
            } else if (stalled >= kPatienceAtFloor) {
                throw RuntimeFailure(failureText(
                    "the overlaps stopped decreasing (jammed) at packing fraction " + std::to_string(phi)));
            }
            fireStep(sums);
        }
    }

    std::vector<double>& positions() { return x_; }
    std::vector<double>& radii() { return r_; }
    long iterations() const { return iterations_; }
    long neighbourBuilds() const { return builds_; }
    long rescales() const { return rescales_; }
    const std::string& targetRegion() const { return target_region_; }

private:
    std::string failureText(const std::string& why) const {
        char buf[256];
        std::snprintf(
            buf, sizeof buf,
            " after %ld sweeps (max relative overlap %.3g, tolerance %.3g, %s packing fraction %.4f)",
            iterations_, last_.max_overlap, params_.overlap_tolerance, target_region_.c_str(),
            regionFraction(shape_, margin_, region_volume_, x_.data(), r_.data(), n_));
        const std::string whole =
            target_region_ == "whole"
                ? " The shape is so thin that its interior (2 mean radii from the walls) is under " +
                      std::to_string(static_cast<int>(100 * kMinInteriorShare)) +
                      " % of its volume, so the target applies to the whole shape, loose wall layers "
                      "included."
                : std::string();
        return "packing " + std::to_string(n_) + " particles in a " + std::string(nameOf(params_.shape)) +
               ": cannot reach the target packing fraction " +
               std::to_string(params_.target_packing_fraction) + " (nor " +
               std::to_string(params_.packing_fraction_tolerance) + " below it): " + why + buf +
               ". The target is probably above this sample's jamming point (about 0.63-0.64 in the interior "
               "of large samples, lower in small ones where the walls dominate); lower "
               "target_packing_fraction, "
               "or raise packing_fraction_tolerance, overlap_tolerance or max_iterations." +
               whole;
    }

    double regionPhi() const {
        return regionFraction(shape_, margin_, region_volume_, x_.data(), r_.data(), n_);
    }

    /// Scales the radii down (or a hair up) until the region φ is the target; the cap fractions make φ only
    /// nearly cubic in the radii, hence the few fixed-point passes.
    void scaleToTarget(double phi) {
        const double target = params_.target_packing_fraction;
        for (int pass = 0; pass < 8 && std::abs(phi / target - 1.0) > 1e-12; ++pass) {
            const double s = std::cbrt(target / phi);
            for (double& ri : r_) {
                ri *= s;
            }
            rescaleRegion(s);
            phi = regionPhi();
        }
        ++rescales_;
    }

    void scaleRadii(double s) {
        for (double& ri : r_) {
            ri *= s;
        }
        rescaleRegion(s);
        ++rescales_;
        resetFire();
        buildNeighbours(); // grown radii need a new list; shrunk ones a tighter one
    }

    /// The interior region follows the mean radius (margin 2 R̄), as in analysePacking.
    void rescaleRegion(double s) {
        mean_radius_ *= s;
        if (target_region_ == "interior") {
            margin_ = 2.0 * mean_radius_;
            region_volume_ = interiorVolume(shape_, margin_);
        }
    }

    void resetFire() {
        std::fill(v_.begin(), v_.end(), 0.0);
        dt_ = kDtStart;
        alpha_ = kAlphaStart;
        positive_steps_ = 0;
    }

    /// Verlet list: for each particle every j ≠ i with |x_i − x_j| < R_i + R_j + skin, in cell order, stored
    /// in fixed-width rows (widened and rebuilt if a row overflows).
    void buildNeighbours() {
        ++builds_;
        const double r_max = *std::max_element(r_.begin(), r_.end());
        grid_.setup(box_lo_, box_hi_, 2.0 * r_max + skin_);
        grid_.bin(x_.data(), n_, "pack.bin");
        for (;;) {
            nbr_.resize(n_ * row_);
            count_.resize(n_);
            const MaxOf widest = reduceOver("pack.neighbours", n_, MaxOf{}, [&](std::size_t i, MaxOf& acc) {
                const Vec3 xi = load3(x_.data(), i);
                const double ri = r_[i];
                std::int32_t* row = nbr_.data() + i * row_;
                std::size_t c = 0;
                grid_.forEachNear(xi, [&](std::int32_t j) {
                    const std::size_t uj = static_cast<std::size_t>(j);
                    if (uj == i) {
                        return;
                    }
                    const double reach = ri + r_[uj] + skin_;
                    if ((load3(x_.data(), uj) - xi).squaredNorm() < reach * reach) {
                        if (c < row_) {
                            row[c] = j;
                        }
                        ++c;
                    }
                });
                count_[i] = static_cast<std::int32_t>(c);
                acc.value = std::max(acc.value, static_cast<double>(c));
            });
            if (widest.value <= static_cast<double>(row_)) {
                break;
            }
            row_ = static_cast<std::size_t>(widest.value) + 8;
        }
        x_ref_ = x_;
    }

    SweepSums computeForces() {
        const double* x = x_.data();
        const double* v = v_.data();
        const double* r = r_.data();
        double* f = f_.data();
        return reduceOver("pack.forces", n_, SweepSums{}, [&](std::size_t i, SweepSums& acc) {
            const Vec3 xi = load3(x, i);
            const double ri = r[i];
            Vec3 fi = Vec3::Zero();
            double worst = 0.0;
            double energy = 0.0;
            const std::int32_t* row = nbr_.data() + i * row_;
            const std::int32_t count = count_[i];
            for (std::int32_t k = 0; k < count; ++k) {
                const std::size_t j = static_cast<std::size_t>(row[k]);
                const Vec3 d = xi - load3(x, j);
                const double sum = ri + r[j];
                const double d2 = d.squaredNorm();
                if (d2 >= sum * sum) {
                    continue;
                }
                const double dist = std::sqrt(d2);
                const double overlap = sum - dist;
                if (dist > 0.0) {
                    fi += (overlap / dist) * d;
                } else {
                    fi += overlap * pairDirection(static_cast<std::int64_t>(i), static_cast<std::int64_t>(j));
                }
                worst = std::max(worst, overlap / sum);
                energy += 0.25 * overlap * overlap; // ½ δ², half of it on each end
            }
            Vec3 fw = Vec3::Zero();
            worst = std::max(worst, walls_.push(xi, ri, fw));
            energy += 0.5 * fw.squaredNorm(); // exact for one wall; an estimate at edges and corners
            fi += fw;
            store3(f, i, fi);
            const Vec3 vi = load3(v, i);
            acc.power += fi.dot(vi);
            acc.force_sq += fi.squaredNorm();
            acc.velocity_sq += vi.squaredNorm();
            acc.energy += energy;
            acc.max_overlap = std::max(acc.max_overlap, worst);
        });
    }

    /// One FIRE step: adapt dt and α from the power F·v, mix the velocity towards the force, kick, drift.
    void fireStep(const SweepSums& sums) {
        double keep = 1.0;
        double mix = 0.0;
        if (sums.power > 0.0) {
            if (++positive_steps_ > kDelaySteps) {
                dt_ = std::min(dt_ * kDtGrow, kDtMax);
                alpha_ *= kAlphaDecay;
            }
            if (sums.force_sq > 0.0) {
                keep = 1.0 - alpha_;
                mix = alpha_ * std::sqrt(sums.velocity_sq / sums.force_sq);
            }
        } else {
            positive_steps_ = 0;
            dt_ *= kDtShrink;
            alpha_ = kAlphaStart;
            keep = 0.0; // stop: the system went uphill
        }
        const double dt = dt_;
        const double max_step = max_step_;
        double* x = x_.data();
        double* v = v_.data();
        const double* f = f_.data();
        const double* x_ref = x_ref_.data();
        const MaxOf moved = reduceOver("pack.update", n_, MaxOf{}, [&](std::size_t i, MaxOf& acc) {
            const Vec3 fi = load3(f, i);
            const Vec3 vi = keep * load3(v, i) + mix * fi + dt * fi;
            Vec3 step = dt * vi;
            const double len = step.norm();
            if (len > max_step) {
                step *= max_step / len;
            }
            const Vec3 xi = load3(x, i) + step;
            store3(v, i, vi);
            store3(x, i, xi);
            acc.value = std::max(acc.value, (xi - load3(x_ref, i)).squaredNorm());
        });
        if (moved.value > 0.25 * skin_ * skin_) { // a particle moved half the skin
            buildNeighbours();
        }
    }

    static constexpr double kMinInteriorShare = 0.1; // interior share of the volume to target it

    // FIRE parameters (Bitzek et al. 2006 defaults, unit masses and unit contact stiffness: the stiffest mode
    // of a sphere with z contacts has ω² ≤ 2z, so dt_max = 0.2 stays well inside 2/ω for z ≤ 40).
    static constexpr double kDtStart = 0.02;
    static constexpr double kDtMax = 0.2;
    static constexpr double kDtGrow = 1.1;
    static constexpr double kDtShrink = 0.5;
    static constexpr double kAlphaStart = 0.1;
    static constexpr double kAlphaDecay = 0.99;
    static constexpr long kDelaySteps = 5;

    const PackingParams& params_;
    SampleParams shape_;
    Walls walls_;
    std::size_t n_;
    std::vector<double> x_, r_, v_, f_, x_ref_;
    Vec3 box_lo_, box_hi_;
    double mean_radius_ = 0.0;
    double margin_ = 0.0;
    double region_volume_ = 0.0;
    std::string target_region_ = "interior";
    double skin_ = 0.0;
    double max_step_ = 0.0;
    CellGrid grid_;
    std::size_t row_ = 48;
    std::vector<std::int32_t> nbr_;
    std::vector<std::int32_t> count_;
    double dt_ = kDtStart;
    double alpha_ = kAlphaStart;
    long positive_steps_ = 0;
    long iterations_ = 0;
    long builds_ = 0;
    long rescales_ = 0;
    SweepSums last_;
};

/// Fabric anisotropy a = sqrt(3/2) ‖F − I/3‖ of F = ⟨n ⊗ n⟩ (F given as xx yy zz xy xz yz sums over count).
double anisotropy(const std::array<double, 6>& sums, long count, std::array<double, 6>* mean_out = nullptr) {
    if (count == 0) {
        return 0.0;
    }
    std::array<double, 6> m{};
    for (int k = 0; k < 6; ++k) {
        m[static_cast<std::size_t>(k)] = sums[static_cast<std::size_t>(k)] / static_cast<double>(count);
    }
    if (mean_out != nullptr) {
        *mean_out = m;
    }
    double norm2 = 0.0;
    for (int k = 0; k < 3; ++k) {
        const double dev = m[static_cast<std::size_t>(k)] - 1.0 / 3.0;
        norm2 += dev * dev;
    }
    for (int k = 3; k < 6; ++k) {
        norm2 += 2.0 * m[static_cast<std::size_t>(k)] * m[static_cast<std::size_t>(k)];
    }
    return std::sqrt(1.5 * norm2);
}

} // namespace

SampleParams shapeParams(const PackingParams& p) {
    SampleParams s;
    s.shape = p.shape;
    s.size = p.size;
    s.radius = p.radius;
    s.height = p.height;
    s.particles = p.particles;
    return s;
}

PackingParams packingParamsFor(const SampleParams& sample, std::uint64_t seed) {
    PackingParams p;
    p.shape = sample.shape;
    p.size = sample.size;
    p.radius = sample.radius;
    p.height = sample.height;
    p.particles = sample.particles;
    p.radius_dispersion = sample.radius_dispersion;
    p.target_packing_fraction = sample.packing_fraction;
    p.target_coordination = sample.coordination;
    p.seed = seed;
    return p;
}

void validatePackingParams(const PackingParams& p) {
    const SampleShape kind = p.shape;
    auto positive = [](double value, const char* key) {
        if (!(value > 0.0) || !std::isfinite(value)) {
            throw std::invalid_argument(std::string("packing: ") + key + " = " + std::to_string(value) +
                                        "; expected a positive finite length (µm)");
        }
    };
    switch (kind) {
    case SampleShape::Box:
        positive(p.size.x(), "size.x");
        positive(p.size.y(), "size.y");
        positive(p.size.z(), "size.z");
        break;
    case SampleShape::Cylinder:
        positive(p.radius, "radius");
        positive(p.height, "height");
        break;
    case SampleShape::Sphere:
    case SampleShape::Hemisphere:
        positive(p.radius, "radius");
        break;
    }
    if (p.min_bonds < 0) {
        throw std::invalid_argument("packing: min_bonds = " + std::to_string(p.min_bonds) +
                                    "; expected >= 0");
    }
    if (p.particles < 1 || p.particles > std::numeric_limits<std::int32_t>::max()) {
        throw std::invalid_argument("packing: particles = " + std::to_string(p.particles) +
                                    "; expected a count from 1 to 2^31 - 1");
    }
    if (p.particles <= p.min_bonds) {
        throw std::invalid_argument("packing: particles = " + std::to_string(p.particles) +
                                    " cannot give every particle min_bonds = " + std::to_string(p.min_bonds) +
                                    " bonds; expected more than min_bonds particles");
    }
    if (!(p.target_packing_fraction > 0.0) || !(p.target_packing_fraction <= 0.74)) {
        throw std::invalid_argument(
            "packing: target_packing_fraction = " + std::to_string(p.target_packing_fraction) +
            " is impossible; expected 0 < phi <= 0.74 (random packings reach about 0.64)");
    }
    if (!(p.packing_fraction_tolerance >= 0.0) ||
        !(p.packing_fraction_tolerance < p.target_packing_fraction)) {
        throw std::invalid_argument(
            "packing: packing_fraction_tolerance = " + std::to_string(p.packing_fraction_tolerance) +
            "; expected 0 <= tol < target_packing_fraction");
    }
    if (!(p.radius_dispersion >= 0.0) || !(p.radius_dispersion < 1.0)) {
        throw std::invalid_argument("packing: radius_dispersion = " + std::to_string(p.radius_dispersion) +
                                    "; expected 0 <= d < 1 (radii uniform in [R(1-d), R(1+d)])");
    }
    if (!(p.target_coordination >= p.min_bonds) || !(p.target_coordination <= 12.0)) {
        throw std::invalid_argument(
            "packing: target_coordination = " + std::to_string(p.target_coordination) +
            "; expected min_bonds (" + std::to_string(p.min_bonds) + ") to 12");
    }
    if (!(p.overlap_tolerance > 0.0) || !(p.overlap_tolerance <= 0.1)) {
        throw std::invalid_argument("packing: overlap_tolerance = " + std::to_string(p.overlap_tolerance) +
                                    "; expected 0 < tol <= 0.1");
    }
    if (p.max_iterations < 1) {
        throw std::invalid_argument("packing: max_iterations = " + std::to_string(p.max_iterations) +
                                    "; expected >= 1");
    }
    // Nominal radii: N 4/3 π R̄³ (1 + d²) = φ V (⟨(1 + dU)³⟩ = 1 + d² for U uniform in [−1, 1]).
    const double volume = shapeVolume(shapeParams(p));
    const double d = p.radius_dispersion;
    const double mean = std::cbrt(p.target_packing_fraction * volume /
                                  (static_cast<double>(p.particles) * 4.0 / 3.0 * kPi * (1.0 + d * d)));
    const double largest = mean * (1.0 + d);
    // The minimiser works with sphere volumes, squared distances and a cell grid of about 2 R: all of them
    // must stay normal finite numbers (a 5e-324 um sphere would give radii of 0).
    if (!std::isnormal(sphereVolume(mean * (1.0 - d))) || !std::isfinite(sphereVolume(largest))) {
        char buf[200];
        std::snprintf(buf, sizeof buf, " give particles of mean radius %.4g um (shape volume %.4g um3)", mean,
                      volume);
        throw std::invalid_argument("packing: " + shapeKeys(p) +
                                    " and particles = " + std::to_string(p.particles) + buf +
                                    ", too small or too large to compute with; expected a shape and particle "
                                    "count whose particle volumes are normal floating-point numbers");
    }
    const double room = inscribedRadius(p);
    if (largest > room) {
        char buf[200];
        std::snprintf(buf, sizeof buf,
                      ": its largest particles (R = %.4g um) do not fit in it (inscribed radius %.4g um)",
                      largest, room);
        throw std::invalid_argument("packing: the " + std::string(nameOf(p.shape)) + " is too small for " +
                                    std::to_string(p.particles) + " particle(s) at packing fraction " +
                                    std::to_string(p.target_packing_fraction) + buf +
                                    "; use more particles or a larger shape");
    }
}

double interiorVolume(const SampleParams& s, double m) {
    const double pi = kPi;
    if (s.shape == SampleShape::Box) {
        const Vec3 inner = (s.size.array() - 2.0 * m).max(0.0).matrix();
        return inner.prod();
    }
    if (s.shape == SampleShape::Cylinder) {
        const double r = std::max(0.0, s.radius - m);
        return pi * r * r * std::max(0.0, s.height - 2.0 * m);
    }
    if (s.shape == SampleShape::Sphere) {
        const double r = std::max(0.0, s.radius - m);
        return 4.0 / 3.0 * pi * r * r * r;
    }
    if (s.shape == SampleShape::Hemisphere) {
        // Ball of radius ρ = R − m cut by the plane z = −m: a cap of height ρ − m.
        const double rho = s.radius - m;
        const double cap = rho - m;
        if (cap <= 0.0) {
            return 0.0;
        }
        return pi * cap * cap * (3.0 * rho - cap) / 3.0;
    }
    throw std::invalid_argument("unknown sample shape");
}

double regionPackingFraction(const SampleParams& shape, double margin, const std::vector<Vec3>& centres,
                             const std::vector<double>& radii) {
    const std::vector<double> x = flatten(centres);
    return regionFraction(shape, margin, interiorVolume(shape, margin), x.data(), radii.data(), radii.size());
}

Packing cutPacking(const Packing& source, const SampleParams& shape, const Vec3& offset) {
    const std::vector<Vec3>& x = source.sample.centres;
    std::vector<std::int32_t> index(x.size(), -1); // source particle → kept particle, −1 if cut away
    Packing out;
    for (std::size_t i = 0; i < x.size(); ++i) {
        const Vec3 y = x[i] - offset;
        const double margin = (1.0 - source.params.overlap_tolerance) * source.sample.radii[i];
        if (insideShape(shape, y) && distanceToBoundary(shape, y) >= margin) {
            index[i] = static_cast<std::int32_t>(out.sample.centres.size());
            out.sample.centres.push_back(y);
            out.sample.radii.push_back(source.sample.radii[i]);
        }
    }
    if (out.sample.centres.size() < 2) {
        throw std::invalid_argument("the cut keeps " + std::to_string(out.sample.centres.size()) +
                                    " particle(s) of the source packing's " + std::to_string(x.size()) +
                                    "; expected at least 2 (is the offset inside the source?)");
    }
    // Source pairs are sorted with i < j; the kept indices keep the source order, so the filtered pairs are
    // too.
    for (const auto& [a, b] : source.bond_pairs) {
        if (index[a] >= 0 && index[b] >= 0) {
            out.bond_pairs.emplace_back(index[a], index[b]);
        }
    }
    out.params = source.params;
    out.params.shape = shape.shape;
    out.params.size = shape.size;
    out.params.radius = shape.radius;
    out.params.height = shape.height;
    out.params.particles = static_cast<long>(out.sample.centres.size());
    out.sample.spacing = source.sample.spacing;
    out.sample.shape_volume = shapeVolume(shape);
    out.report = analysePacking(out.params, out.sample.centres, out.sample.radii, out.bond_pairs);
    out.report.target_region = source.report.target_region;
    out.report.gap_tolerance = source.report.gap_tolerance;
    out.report.bonds_added_for_min = source.report.bonds_added_for_min;
    out.report.iterations = source.report.iterations;
    out.report.neighbour_builds = source.report.neighbour_builds;
    out.report.radius_rescales = source.report.radius_rescales;
    out.report.seconds = source.report.seconds;
    return out;
}

Packing packRandom(const PackingParams& params) {
    const auto start = std::chrono::steady_clock::now();
    validatePackingParams(params);
    const SampleParams shape = shapeParams(params);
    const std::size_t n = static_cast<std::size_t>(params.particles);
    const double volume = shapeVolume(shape);

    // 1. Draw radii and centres (serial, seeded).
    std::mt19937_64 rng(params.seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<double> radii(n);
    for (double& r : radii) {
        r = 1.0 + params.radius_dispersion * (2.0 * unit(rng) - 1.0);
    }
    double solid = 0.0;
    for (double r : radii) {
        solid += sphereVolume(r);
    }
    const double scale = std::cbrt(params.target_packing_fraction * volume / solid);
    for (double& r : radii) {
        r *= scale;
    }
    Vec3 lo;
    Vec3 hi;
    shapeBounds(params, lo, hi);
    std::vector<Vec3> drawn(n);
    for (Vec3& x : drawn) {
        do {
            for (int c = 0; c < 3; ++c) {
                x[c] = lo[c] + (hi[c] - lo[c]) * unit(rng);
            }
        } while (!insideShape(shape, x));
    }
    // Morton order from the start: neighbours in space are neighbours in memory while compacting.
    {
        const std::vector<std::size_t> order = mortonOrder(drawn);
        std::vector<Vec3> x(n);
        std::vector<double> r(n);
        for (std::size_t k = 0; k < n; ++k) {
            x[k] = drawn[order[k]];
            r[k] = radii[order[k]];
        }
        drawn.swap(x);
        radii.swap(r);
    }

    // 2–3. Compact inside the walls and reach the target φ.
    Compactor compactor(params, flatten(drawn), radii);
    try {
        compactor.run();
    } catch (const CellGridError& e) { // validatePackingParams keeps the radii representable: a safeguard
        throw std::invalid_argument("packing: " + shapeKeys(params) +
                                    " and particles = " + std::to_string(params.particles) + ": " + e.what());
    }

    // 4. Morton order of the final centres, bonds, report.
    std::vector<Vec3> centres(n);
    for (std::size_t i = 0; i < n; ++i) {
        centres[i] = load3(compactor.positions().data(), i);
    }
    const std::vector<std::size_t> order = mortonOrder(centres);
    Packing out;
    out.params = params;
    out.sample.centres.resize(n);
    out.sample.radii.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
        out.sample.centres[k] = centres[order[k]];
        out.sample.radii[k] = compactor.radii()[order[k]];
    }
    BondSelection selection =
        selectBonds(out.sample.centres, out.sample.radii, params.target_coordination, params.min_bonds);
    out.bond_pairs = std::move(selection.pairs);
    out.report = analysePacking(params, out.sample.centres, out.sample.radii, out.bond_pairs);
    out.sample.spacing = 2.0 * out.report.mean_radius;
    out.sample.shape_volume = volume;
    out.report.target_region = compactor.targetRegion();
    out.report.gap_tolerance = selection.gap_tolerance;
    out.report.bonds_added_for_min = selection.added_for_min_bonds;
    out.report.iterations = compactor.iterations();
    out.report.neighbour_builds = compactor.neighbourBuilds();
    out.report.radius_rescales = compactor.rescales();
    out.report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
}

namespace {

/// selectBonds with one candidate cap; returns false (and the particle in `isolated_particle`) when some
/// particle has fewer than min_bonds candidates.
bool selectWithCap(const std::vector<Vec3>& centres, const std::vector<double>& radii,
                   double target_coordination, int min_bonds, double gap_cap, BondSelection& out,
                   std::size_t& isolated_particle) {
    const std::size_t n = centres.size();
    struct Candidate {
        double gap;
        std::int32_t i, j;
    };
    std::vector<Candidate> cand;
    forEachClosePair(centres, radii, gap_cap, [&](std::int32_t i, std::int32_t j, double g) {
        cand.push_back({g, i, j});
    });
    std::sort(cand.begin(), cand.end(), [](const Candidate& a, const Candidate& b) {
        if (a.gap != b.gap) {
            return a.gap < b.gap;
        }
        return a.i != b.i ? a.i < b.i : a.j < b.j;
    });
    const long wanted = std::llround(target_coordination * static_cast<double>(n) / 2.0);
    if (wanted > static_cast<long>(cand.size())) {
        isolated_particle = n; // not one particle: too few candidates overall; the caller widens the cap
        return false;
    }
    // Per-particle candidate lists in rank order (rank = position in `cand`).
    std::vector<std::int32_t> offset(n + 1, 0);
    for (const Candidate& c : cand) {
        ++offset[static_cast<std::size_t>(c.i) + 1];
        ++offset[static_cast<std::size_t>(c.j) + 1];
    }
    for (std::size_t p = 0; p < n; ++p) {
        offset[p + 1] += offset[p];
    }
    std::vector<std::int32_t> ranks(static_cast<std::size_t>(offset[n]));
    {
        std::vector<std::int32_t> fill(offset.begin(), offset.end() - 1);
        for (std::size_t k = 0; k < cand.size(); ++k) {
            ranks[static_cast<std::size_t>(fill[static_cast<std::size_t>(cand[k].i)]++)] =
                static_cast<std::int32_t>(k);
            ranks[static_cast<std::size_t>(fill[static_cast<std::size_t>(cand[k].j)]++)] =
                static_cast<std::int32_t>(k);
        }
    }
    // Bonds the first `take` candidates, then tops every particle up to min_bonds with its nearest other
    // candidates (particles in index order); returns the number of bonds added and marks them in `extra`.
    std::vector<int> degree(n);
    std::vector<std::uint8_t> extra(cand.size());
    auto complete = [&](long take, bool& isolated) {
        std::fill(degree.begin(), degree.end(), 0);
        std::fill(extra.begin(), extra.end(), std::uint8_t{0});
        for (long k = 0; k < take; ++k) {
            ++degree[static_cast<std::size_t>(cand[static_cast<std::size_t>(k)].i)];
            ++degree[static_cast<std::size_t>(cand[static_cast<std::size_t>(k)].j)];
        }
        long added = 0;
        isolated = false;
        // Two passes: first only partners that are short of bonds too (one bond serves both), then any.
        for (int pass = 0; pass < 2; ++pass) {
            for (std::size_t p = 0; p < n; ++p) {
                for (std::int32_t e = offset[p]; e < offset[p + 1] && degree[p] < min_bonds; ++e) {
                    const std::size_t k = static_cast<std::size_t>(ranks[static_cast<std::size_t>(e)]);
                    if (static_cast<long>(k) < take || extra[k] != 0) {
                        continue;
                    }
                    const std::size_t q = static_cast<std::size_t>(cand[k].i) == p
                                              ? static_cast<std::size_t>(cand[k].j)
                                              : static_cast<std::size_t>(cand[k].i);
                    if (pass == 0 && degree[q] >= min_bonds) {
                        continue;
                    }
                    extra[k] = 1;
                    ++degree[p];
                    ++degree[q];
                    ++added;
                }
                if (pass == 1 && degree[p] < min_bonds) {
                    isolated = true;
                }
            }
        }
        return added;
    };
    // Smallest take with take + added ≥ wanted (take + added is non-decreasing up to ±1 steps), then the
    // closer of it and its predecessor.
    bool isolated = false;
    long lo = 0;
    long hi = wanted;
    while (lo < hi) {
        const long mid = lo + (hi - lo) / 2;
        if (mid + complete(mid, isolated) >= wanted) {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    long take = lo;
    if (take > 0) {
        const long below = take - 1 + complete(take - 1, isolated);
        const long at = take + complete(take, isolated);
        if (std::abs(below - wanted) < std::abs(at - wanted)) {
            take = take - 1;
        }
    }
    out.added_for_min_bonds = complete(take, isolated);
    if (isolated) {
        for (std::size_t p = 0; p < n; ++p) {
            if (degree[p] < min_bonds) {
                isolated_particle = p;
                return false;
            }
        }
    }
    out.gap_tolerance = take > 0 ? cand[static_cast<std::size_t>(take - 1)].gap : 0.0;
    for (std::size_t k = 0; k < cand.size(); ++k) {
        if (static_cast<long>(k) < take || extra[k] != 0) {
            out.pairs.emplace_back(cand[k].i, cand[k].j);
        }
    }
    std::sort(out.pairs.begin(), out.pairs.end());
    return true;
}

} // namespace

BondSelection selectBonds(const std::vector<Vec3>& centres, const std::vector<double>& radii,
                          double target_coordination, int min_bonds, double gap_cap) {
    const std::size_t n = centres.size();
    if (radii.size() != n) {
        throw std::invalid_argument("selectBonds: " + std::to_string(n) + " centres but " +
                                    std::to_string(radii.size()) + " radii");
    }
    if (!(target_coordination >= 0.0) || min_bonds < 0 || !(gap_cap > 0.0)) {
        throw std::invalid_argument(
            "selectBonds: expected target_coordination >= 0, min_bonds >= 0, gap_cap > 0");
    }
    if (n < 2) {
        return {};
    }
    // Particles wedged in a corner of the shape can have fewer than min_bonds neighbours within the cap:
    // widen it (doubling, at most 4 times) rather than leave them loose.
    double cap = gap_cap;
    std::size_t isolated = 0;
    for (int attempt = 0; attempt < 5; ++attempt, cap *= 2.0) {
        BondSelection out;
        if (selectWithCap(centres, radii, target_coordination, min_bonds, cap, out, isolated)) {
            return out;
        }
    }
    if (isolated == n) {
        throw RuntimeFailure(
            "bond selection: mean coordination " + std::to_string(target_coordination) + " needs " +
            std::to_string(std::llround(target_coordination * static_cast<double>(n) / 2.0)) +
            " bonds but fewer pairs have a normalised gap below " + std::to_string(cap / 2.0) +
            " (is this a dense packing?)");
    }
    const Vec3& x = centres[isolated];
    char where[128];
    std::snprintf(where, sizeof where, " at (%.4g, %.4g, %.4g) um", x.x(), x.y(), x.z());
    throw RuntimeFailure("bond selection: particle " + std::to_string(isolated) + where + " has fewer than " +
                         std::to_string(min_bonds) + " neighbours within a normalised gap of " +
                         std::to_string(cap / 2.0) + "; cannot give it " + std::to_string(min_bonds) +
                         " bonds");
}

std::vector<std::pair<std::int32_t, std::int32_t>> selectBondPairs(const std::vector<Vec3>& centres,
                                                                   const std::vector<double>& radii,
                                                                   double target_coordination,
                                                                   int min_bonds) {
    return selectBonds(centres, radii, target_coordination, min_bonds).pairs;
}

Bonds makeBonds(const Particles& particles, const std::vector<std::pair<std::int32_t, std::int32_t>>& pairs,
                const MaterialParams& material) {
    Bonds bonds;
    const auto n = static_cast<std::int32_t>(particles.size());
    for (const auto& [a, b] : pairs) {
        if (a < 0 || b < 0 || a >= n || b >= n || a == b) {
            throw std::invalid_argument("makeBonds: pair (" + std::to_string(a) + ", " + std::to_string(b) +
                                        ") is not two distinct particles of " + std::to_string(n));
        }
        bonds.add(particles, a, b, material);
    }
    return bonds;
}

PackingReport analysePacking(const PackingParams& params, const std::vector<Vec3>& centres,
                             const std::vector<double>& radii,
                             const std::vector<std::pair<std::int32_t, std::int32_t>>& pairs) {
    const std::size_t n = centres.size();
    if (radii.size() != n) {
        throw std::invalid_argument("analysePacking: " + std::to_string(n) + " centres but " +
                                    std::to_string(radii.size()) + " radii");
    }
    const SampleParams shape = shapeParams(params);
    PackingReport rep;
    rep.particles = static_cast<long>(n);
    rep.bonds = static_cast<long>(pairs.size());
    rep.shape_volume = shapeVolume(shape);
    if (n == 0) {
        return rep;
    }
    double sum_r = 0.0;
    double solid = 0.0;
    rep.min_radius = radii[0];
    rep.max_radius = radii[0];
    for (double r : radii) {
        sum_r += r;
        solid += sphereVolume(r);
        rep.min_radius = std::min(rep.min_radius, r);
        rep.max_radius = std::max(rep.max_radius, r);
    }
    rep.mean_radius = sum_r / static_cast<double>(n);
    rep.packing_fraction = solid / rep.shape_volume;
    rep.interior_margin = 2.0 * rep.mean_radius;
    rep.interior_volume = interiorVolume(shape, rep.interior_margin);
    rep.packing_fraction_interior = regionPackingFraction(shape, rep.interior_margin, centres, radii);

    // Surface particles, interior flags, wall overlaps.
    std::vector<std::uint8_t> interior(n);
    long surface = 0;
    Walls walls;
    walls.kind = params.shape;
    walls.size = params.size;
    walls.radius = params.radius;
    walls.height = params.height;
    for (std::size_t i = 0; i < n; ++i) {
        const double dist = distanceToBoundary(shape, centres[i]);
        interior[i] = dist >= rep.interior_margin ? 1 : 0;
        surface += dist < 1.5 * radii[i] ? 1 : 0;
        Vec3 unused = Vec3::Zero();
        rep.max_wall_overlap = std::max(rep.max_wall_overlap, walls.push(centres[i], radii[i], unused));
    }
    rep.surface_fraction = static_cast<double>(surface) / static_cast<double>(n);

    // Overlaps between all pairs (not only bonded ones).
    forEachClosePair(centres, radii, 1e-9, [&](std::int32_t, std::int32_t, double g) {
        rep.max_overlap = std::max(rep.max_overlap, -g);
    });

    // Coordination, fabric, gaps of bonded pairs.
    std::vector<int> degree(n, 0);
    std::array<double, 6> fabric_all{};
    std::array<double, 6> fabric_in{};
    long bonds_in = 0;
    double gap_sum = 0.0;
    rep.gap_min = std::numeric_limits<double>::infinity();
    rep.gap_max = -std::numeric_limits<double>::infinity();
    for (const auto& [a, b] : pairs) {
        if (a < 0 || b < 0 || static_cast<std::size_t>(a) >= n || static_cast<std::size_t>(b) >= n ||
            a == b) {
            throw std::invalid_argument("analysePacking: bond (" + std::to_string(a) + ", " +
                                        std::to_string(b) + ") is not two distinct particles of " +
                                        std::to_string(n));
        }
        const std::size_t ua = static_cast<std::size_t>(a);
        const std::size_t ub = static_cast<std::size_t>(b);
        ++degree[ua];
        ++degree[ub];
        const Vec3 d = centres[ub] - centres[ua];
        const double len = d.norm();
        const double g = len / (radii[ua] + radii[ub]) - 1.0;
        gap_sum += g;
        rep.gap_min = std::min(rep.gap_min, g);
        rep.gap_max = std::max(rep.gap_max, g);
        if (!(len > 0.0)) {
            continue;
        }
        const Vec3 u = d / len;
        const std::array<double, 6> nn = {u.x() * u.x(), u.y() * u.y(), u.z() * u.z(),
                                          u.x() * u.y(), u.x() * u.z(), u.y() * u.z()};
        for (std::size_t k = 0; k < 6; ++k) {
            fabric_all[k] += nn[k];
        }
        if (interior[ua] != 0 && interior[ub] != 0) {
            ++bonds_in;
            for (std::size_t k = 0; k < 6; ++k) {
                fabric_in[k] += nn[k];
            }
        }
    }
    if (pairs.empty()) {
        rep.gap_min = rep.gap_max = 0.0;
    } else {
        rep.gap_mean = gap_sum / static_cast<double>(pairs.size());
    }
    rep.fabric_anisotropy = anisotropy(fabric_all, rep.bonds, &rep.fabric);
    rep.fabric_anisotropy_interior = anisotropy(fabric_in, bonds_in);
    rep.coordination_mean = 2.0 * static_cast<double>(pairs.size()) / static_cast<double>(n);
    rep.coordination_min = *std::min_element(degree.begin(), degree.end());
    rep.coordination_max = *std::max_element(degree.begin(), degree.end());
    rep.coordination_histogram.assign(static_cast<std::size_t>(rep.coordination_max) + 1, 0);
    long interior_count = 0;
    long interior_degree = 0;
    for (std::size_t i = 0; i < n; ++i) {
        ++rep.coordination_histogram[static_cast<std::size_t>(degree[i])];
        if (interior[i] != 0) {
            ++interior_count;
            interior_degree += degree[i];
        }
    }
    rep.coordination_mean_interior =
        interior_count > 0 ? static_cast<double>(interior_degree) / static_cast<double>(interior_count) : 0.0;
    return rep;
}

std::string formatPackingReport(const PackingReport& r) {
    std::ostringstream s;
    char line[256];
    auto put = [&](const char* fmt, auto... args) {
        std::snprintf(line, sizeof line, fmt, args...);
        s << line << '\n';
    };
    put("particles              %ld", r.particles);
    put("bonds                  %ld", r.bonds);
    put("radius (um)            mean %.6g  min %.6g  max %.6g", r.mean_radius, r.min_radius, r.max_radius);
    put("packing fraction       whole %.4f  interior %.4f  (interior: >= %.4g um from the boundary, %.4g "
        "um3; "
        "target region: %s)",
        r.packing_fraction, r.packing_fraction_interior, r.interior_margin, r.interior_volume,
        r.target_region.c_str());
    put("coordination           mean %.4f  interior %.4f  min %d  max %d", r.coordination_mean,
        r.coordination_mean_interior, r.coordination_min, r.coordination_max);
    std::string hist = "coordination histogram";
    for (std::size_t k = 0; k < r.coordination_histogram.size(); ++k) {
        if (r.coordination_histogram[k] != 0) {
            hist += "  " + std::to_string(k) + ":" + std::to_string(r.coordination_histogram[k]);
        }
    }
    s << hist << '\n';
    put("fabric <n n>           xx %.4f  yy %.4f  zz %.4f  xy %.4f  xz %.4f  yz %.4f", r.fabric[0],
        r.fabric[1], r.fabric[2], r.fabric[3], r.fabric[4], r.fabric[5]);
    put("fabric anisotropy      %.4f  interior %.4f  (sqrt(3/2)|F - I/3|: 0 isotropic, 1 all parallel; "
        "statistical floor ~1/sqrt(bonds) = %.4f)",
        r.fabric_anisotropy, r.fabric_anisotropy_interior,
        r.bonds > 0 ? 1.0 / std::sqrt(static_cast<double>(r.bonds)) : 0.0);
    put("bonded gaps d/(Ri+Rj)-1  min %.3e  mean %.3e  max %.3e  (selection tolerance %.3e, %ld added for "
        "min bonds)",
        r.gap_min, r.gap_mean, r.gap_max, r.gap_tolerance, r.bonds_added_for_min);
    put("max overlap            pairs %.3e  walls %.3e", r.max_overlap, r.max_wall_overlap);
    put("surface particles      %.4f (centre within 1.5 R of the boundary)", r.surface_fraction);
    put("minimiser              %ld sweeps, %ld neighbour builds, %ld radius rescales, %.2f s", r.iterations,
        r.neighbour_builds, r.radius_rescales, r.seconds);
    return s.str();
}

} // namespace vitrum
