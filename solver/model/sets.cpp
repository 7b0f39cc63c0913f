#include "solver/model/sets.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "solver/model/particles.hpp"

namespace vitrum {

std::vector<SelectorClause> parseSelector(const std::string& text) {
    std::istringstream in(text);
    std::vector<std::string> words;
    for (std::string w; in >> w;) {
        words.push_back(w);
    }
    const std::string expected = "expected clauses joined by 'and': all | surface | dome | top layer | bottom layer | "
                                 "<x|y|z|r|d> <op> <number> with op one of < <= > >=";
    std::vector<SelectorClause> clauses;
    std::size_t k = 0;
    while (k < words.size()) {
        SelectorClause c;
        const std::string& w = words[k];
        if (w == "all" || w == "surface" || w == "dome") {
            c.kind = w == "all" ? SelectorClause::Kind::All
                     : w == "surface" ? SelectorClause::Kind::Surface
                                      : SelectorClause::Kind::Dome;
            k += 1;
        } else if ((w == "top" || w == "bottom") && k + 1 < words.size() && words[k + 1] == "layer") {
            c.kind = w == "top" ? SelectorClause::Kind::TopLayer : SelectorClause::Kind::BottomLayer;
            k += 2;
        } else if (w.size() == 1 && std::string("xyzrd").find(w[0]) != std::string::npos && k + 2 < words.size()) {
            c.kind = SelectorClause::Kind::Compare;
            c.coord = w[0];
            c.op = words[k + 1];
            if (c.op != "<" && c.op != "<=" && c.op != ">" && c.op != ">=") {
                throw std::invalid_argument("unknown comparison '" + c.op + "' in '" + text + "'; " + expected);
            }
            std::size_t used = 0;
            try {
                c.value = std::stod(words[k + 2], &used);
            } catch (const std::exception&) {
                used = 0;
            }
            if (used != words[k + 2].size()) {
                throw std::invalid_argument("'" + words[k + 2] + "' is not a number in '" + text + "'; " + expected);
            }
            k += 3;
        } else {
            throw std::invalid_argument("cannot read '" + w + "' in '" + text + "'; " + expected);
        }
        clauses.push_back(c);
        if (k < words.size()) {
            if (words[k] != "and" || k + 1 == words.size()) {
                throw std::invalid_argument("expected 'and' followed by a clause after clause " +
                                            std::to_string(clauses.size()) + " in '" + text + "'; " + expected);
            }
            ++k;
        }
    }
    if (clauses.empty()) {
        throw std::invalid_argument("empty selector; " + expected);
    }
    return clauses;
}

std::vector<std::int32_t> selectParticles(const std::vector<SelectorClause>& clauses, const Particles& p,
                                          double length_factor) {
    const std::size_t n = p.size();
    double z_top = -1e300;
    double z_bottom = 1e300;
    double r_min = 1e300;
    double r_dome = 0.0; // radius of the sphere about the origin that bounds the sample (sphere, hemisphere)
    for (std::size_t i = 0; i < n; ++i) {
        z_top = std::max(z_top, p.position[3 * i + 2]);
        z_bottom = std::min(z_bottom, p.position[3 * i + 2]);
        r_min = std::min(r_min, p.radius[i]);
        r_dome = std::max(r_dome, load3(p.position.data(), i).norm() + p.radius[i]);
    }
    auto matches = [&](const SelectorClause& c, std::size_t i) {
        const Vec3 x = load3(p.position.data(), i);
        const bool surface = (p.flags[i] & kSurface) != 0;
        const bool top = x.z() >= z_top - 0.5 * r_min;
        switch (c.kind) {
        case SelectorClause::Kind::All:
            return true;
        case SelectorClause::Kind::Surface:
            return surface;
        case SelectorClause::Kind::Dome:
            // The curved boundary only: within 1.5 R of the bounding sphere about the origin. (Surface particles
            // near the flat face of a hemisphere are free: fixing them would stiffen the indented surface.)
            return surface && !top && r_dome - x.norm() < 1.5 * p.radius[i];
        case SelectorClause::Kind::TopLayer:
            return top;
        case SelectorClause::Kind::BottomLayer:
            return x.z() <= z_bottom + 0.5 * r_min;
        case SelectorClause::Kind::Compare:
            break;
        }
        const double v = c.coord == 'x'   ? x.x()
                         : c.coord == 'y' ? x.y()
                         : c.coord == 'z' ? x.z()
                         : c.coord == 'r' ? std::hypot(x.x(), x.y())
                                          : x.norm();
        const double ref = c.value * length_factor;
        return c.op == "<" ? v < ref : c.op == "<=" ? v <= ref : c.op == ">" ? v > ref : v >= ref;
    };
    std::vector<std::int32_t> members;
    for (std::size_t i = 0; i < n; ++i) {
        if (std::all_of(clauses.begin(), clauses.end(), [&](const SelectorClause& c) { return matches(c, i); })) {
            members.push_back(static_cast<std::int32_t>(i));
        }
    }
    return members;
}

} // namespace vitrum
