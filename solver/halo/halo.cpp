#include "solver/halo/halo.hpp"

#include <cstring>
#include <map>
#include <span>

#include "solver/model/model.hpp"

namespace vitrum {

std::size_t Halo::sent() const {
    std::size_t n = 0;
    for (const auto& s : send) n += s.size();
    return n;
}

std::size_t Halo::received() const {
    std::size_t n = 0;
    for (const auto& r : receive) n += r.second;
    return n;
}

void forwardToGhosts(Domain& d, const std::vector<HaloField>& fields) {
    std::size_t row = 0;
    for (const HaloField& f : fields) row += f.bytes;
    // One message per peer: its bond-halo rows, then its contact-halo rows.
    std::map<int, std::pair<int, int>> at; // peer → (index in bond halo, index in contact halo), -1 if none
    for (std::size_t k = 0; k < d.bond_halo.peers.size(); ++k) at[d.bond_halo.peers[k]] = {static_cast<int>(k), -1};
    for (std::size_t k = 0; k < d.contact_halo.peers.size(); ++k) {
        auto [it, fresh] = at.try_emplace(d.contact_halo.peers[k], -1, static_cast<int>(k));
        if (!fresh) it->second.second = static_cast<int>(k);
    }
    std::vector<int> peers;
    std::vector<std::vector<std::byte>> out, in;
    for (const auto& [q, idx] : at) {
        peers.push_back(q);
        std::size_t sends = 0, receives = 0;
        if (idx.first >= 0) {
            sends += d.bond_halo.send[static_cast<std::size_t>(idx.first)].size();
            receives += d.bond_halo.receive[static_cast<std::size_t>(idx.first)].second;
        }
        if (idx.second >= 0) {
            sends += d.contact_halo.send[static_cast<std::size_t>(idx.second)].size();
            receives += d.contact_halo.receive[static_cast<std::size_t>(idx.second)].second;
        }
        std::vector<std::byte> buffer(sends * row);
        std::byte* w = buffer.data();
        auto pack = [&](const std::vector<std::int32_t>& rows) {
            for (std::int32_t p : rows) {
                for (const HaloField& f : fields) {
                    std::memcpy(w, static_cast<const std::byte*>(f.data) + static_cast<std::size_t>(p) * f.bytes, f.bytes);
                    w += f.bytes;
                }
            }
        };
        if (idx.first >= 0) pack(d.bond_halo.send[static_cast<std::size_t>(idx.first)]);
        if (idx.second >= 0) pack(d.contact_halo.send[static_cast<std::size_t>(idx.second)]);
        out.push_back(std::move(buffer));
        in.emplace_back(receives * row);
    }
    std::vector<std::span<const std::byte>> send_spans;
    std::vector<std::span<std::byte>> recv_spans;
    for (std::size_t k = 0; k < peers.size(); ++k) {
        send_spans.emplace_back(out[k]);
        recv_spans.emplace_back(in[k]);
    }
    d.comm->exchange(peers, send_spans, recv_spans);
    for (std::size_t k = 0; k < peers.size(); ++k) {
        const auto& idx = at[peers[k]];
        const std::byte* r = in[k].data();
        auto unpack = [&](std::pair<std::size_t, std::size_t> range) {
            for (std::size_t p = range.first; p < range.first + range.second; ++p) {
                for (const HaloField& f : fields) {
                    std::memcpy(static_cast<std::byte*>(f.data) + p * f.bytes, r, f.bytes);
                    r += f.bytes;
                }
            }
        };
        if (idx.first >= 0) unpack(d.bond_halo.receive[static_cast<std::size_t>(idx.first)]);
        if (idx.second >= 0) unpack(d.contact_halo.receive[static_cast<std::size_t>(idx.second)]);
    }
}

void forwardState(Domain& d, Model& m) {
    Particles& p = m.particles;
    std::vector<HaloField> fields = {{p.position.data(), 3 * sizeof(double)}, {p.orientation.data(), 4 * sizeof(double)}};
    if (d.velocities) {
        fields.push_back({p.velocity.data(), 3 * sizeof(double)});
        fields.push_back({p.angular_velocity.data(), 3 * sizeof(double)});
    }
    forwardToGhosts(d, fields);
}

} // namespace vitrum
