#include "solver/measure/cracks.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace vitrum {

namespace {

constexpr int kSectors = 24;              ///< azimuthal sectors of 15°
constexpr double kRingCoverage = 0.75;    ///< a closed ring covers at least this fraction of the sectors
constexpr double kRadialPeak = 3.0;       ///< a radial crack's sector holds this many times the median count

struct Point {
    double r, phi, d, x, y;
};

int sectorOf(double phi) {
    const double t = (phi + std::numbers::pi) / (2.0 * std::numbers::pi); // [0, 1]
    return std::min(kSectors - 1, static_cast<int>(t * kSectors));
}

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    const std::size_t m = v.size() / 2;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(m), v.end());
    return v[m];
}

/// Least-squares line r = r0 + k d through the points; returns false with fewer than 2 distinct depths.
bool fitFlank(const std::vector<const Point*>& pts, double& r0, double& k) {
    if (pts.size() < 2) return false;
    double sd = 0, sr = 0, sdd = 0, sdr = 0;
    for (const Point* p : pts) {
        sd += p->d;
        sr += p->r;
        sdd += p->d * p->d;
        sdr += p->d * p->r;
    }
    const double n = static_cast<double>(pts.size());
    const double det = n * sdd - sd * sd;
    if (!(det > 1e-12 * n * n)) return false;
    k = (n * sdr - sd * sr) / det;
    r0 = (sr - k * sd) / n;
    return true;
}

} // namespace

CrackPattern classifyCracks(std::size_t n, const double* centres, const CrackParams& c) {
    CrackPattern out;
    out.released = static_cast<long>(n);
    const double a = c.contact_radius;
    std::vector<Point> pts(n);
    for (std::size_t i = 0; i < n; ++i) {
        const double x = centres[3 * i] - c.axis.x(), y = centres[3 * i + 1] - c.axis.y();
        pts[i] = {std::hypot(x, y), std::atan2(y, x), c.surface - centres[3 * i + 2], x, y};
    }
    std::vector<const Point*> ring, outer, sub;
    for (const Point& p : pts) {
        const bool under = c.square_half_side > 0.0
                               ? std::max(std::abs(p.x), std::abs(p.y)) <= c.square_half_side
                               : p.r <= a;
        if (under) {
            ++out.core;
            out.deep_core += p.d > 1.5 * a ? 1 : 0;
            continue;
        }
        outer.push_back(&p);
        if (p.d <= c.band) {
            ring.push_back(&p);
        } else {
            sub.push_back(&p);
        }
    }
    out.ring_band = static_cast<long>(ring.size());
    out.subsurface = static_cast<long>(sub.size());

    // Ring / cone: coverage of the surface band outside the contact.
    std::vector<long> ring_count(kSectors, 0);
    for (const Point* p : ring) ++ring_count[static_cast<std::size_t>(sectorOf(p->phi))];
    const long covered = std::count_if(ring_count.begin(), ring_count.end(), [](long k) { return k > 0; });
    out.ring_coverage = static_cast<double>(covered) / kSectors;
    std::vector<const Point*> flank;
    std::vector<double> radii;
    for (const Point* p : ring) radii.push_back(p->r);
    std::sort(radii.begin(), radii.end());
    const double spread = radii.empty() ? 0.0 : radii[3 * radii.size() / 4] - radii[radii.size() / 4];
    const double ring_radius = radii.empty() ? 0.0 : radii[radii.size() / 2];
    // A ring is thin: its interquartile radial spread is within 2 band (a shallow cone's band of depth spans
    // band cot β radially: 1.5 band at 35°, 2.5 band at 22°) or a quarter of its radius; scattered damage
    // around the contact fills the band with a spread of the order of its radius.
    const bool thin = spread <= std::max(3.0 * c.band, 0.25 * ring_radius);
    if (static_cast<long>(ring.size()) >= c.min_particles && out.ring_coverage >= kRingCoverage && thin) {
        out.cone = true;
        out.cone_radius = ring_radius;
        // The flank: start from the vertical line through the ring, keep the outer particles within 2 band
        // of the current line and refit, until the kept set settles (it grows down the flank pass by pass).
        double r0 = out.cone_radius, k = 0.0;
        std::size_t kept = 0;
        for (int pass = 0; pass < 20; ++pass) {
            flank.clear();
            for (const Point* p : outer) {
                if (std::abs(p->r - (r0 + k * p->d)) <= 2.0 * c.band) flank.push_back(p);
            }
            double r1 = r0, k1 = k;
            if (!fitFlank(flank, r1, k1)) break;
            const bool settled = flank.size() == kept && std::abs(k1 - k) < 1e-9 * (1.0 + std::abs(k));
            r0 = r1;
            k = k1;
            kept = flank.size();
            if (settled) break;
        }
        double deepest = 0.0;
        for (const Point* p : flank) deepest = std::max(deepest, p->d);
        // A flank that reaches below the band is a cone; a ring alone has no angle.
        if (deepest > 2.0 * c.band && static_cast<long>(flank.size()) >= c.min_particles) {
            out.cone_angle = std::atan2(1.0, k) * 180.0 / std::numbers::pi; // flank to surface: tan β = 1/k
        }
    }

    // Radial cracks: azimuthal peaks of the outer near-surface particles (depth within max(band, a)) off the
    // cone flank.
    std::vector<long> count(kSectors, 0);
    std::vector<double> rmin(kSectors, 1e300), rmax(kSectors, -1e300);
    auto onFlank = [&](const Point* p) { return std::find(flank.begin(), flank.end(), p) != flank.end(); };
    for (const Point* p : outer) {
        if (p->d > std::max(c.band, a) || onFlank(p)) continue; // the cone's own particles are not radial cracks
        const std::size_t s = static_cast<std::size_t>(sectorOf(p->phi));
        ++count[s];
        rmin[s] = std::min(rmin[s], p->r);
        rmax[s] = std::max(rmax[s], p->r);
    }
    std::vector<double> counts(count.begin(), count.end());
    const double typical = median(counts);
    std::vector<char> peak(kSectors, 0);
    for (int s = 0; s < kSectors; ++s) {
        const auto u = static_cast<std::size_t>(s);
        peak[u] = count[u] >= c.min_particles && static_cast<double>(count[u]) >= kRadialPeak * std::max(typical, 1.0) &&
                  rmax[u] - rmin[u] >= a;
    }
    if (std::all_of(peak.begin(), peak.end(), [](char p) { return p; })) {
        out.radial = 0; // every sector dense alike: a ring, not radial cracks
    } else {
        for (int s = 0; s < kSectors; ++s) {
            // Count the first sector of each run of peaks (circularly).
            out.radial += peak[static_cast<std::size_t>(s)] && !peak[static_cast<std::size_t>((s + kSectors - 1) % kSectors)];
        }
    }

    out.median = out.deep_core >= c.min_particles;

    // Lateral: the densest depth slab of the sub-surface outer particles off the cone flank.
    std::vector<const Point*> sheet_candidates;
    for (const Point* p : sub) {
        if (!onFlank(p)) sheet_candidates.push_back(p);
    }
    if (static_cast<long>(sheet_candidates.size()) >= c.min_particles && c.band > 0.0) {
        double dmax = 0.0;
        for (const Point* p : sheet_candidates) dmax = std::max(dmax, p->d);
        long best = 0;
        double best_depth = 0.0;
        for (double lo = c.band; lo <= dmax; lo += 0.5 * c.band) {
            long k = 0;
            double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
            for (const Point* p : sheet_candidates) {
                if (p->d < lo || p->d > lo + c.band) continue;
                ++k;
                xmin = std::min(xmin, p->x);
                xmax = std::max(xmax, p->x);
                ymin = std::min(ymin, p->y);
                ymax = std::max(ymax, p->y);
            }
            if (k > best && xmax - xmin >= 2.0 * a && ymax - ymin >= 2.0 * a) {
                best = k;
                best_depth = lo + 0.5 * c.band;
            }
        }
        if (best >= c.min_particles && 2 * best >= static_cast<long>(sheet_candidates.size())) {
            out.lateral = true;
            out.lateral_depth = best_depth;
        }
    }
    return out;
}

} // namespace vitrum
