// Particle and bond maps as VTK XML unstructured grids (.vtu) plus the ParaView time collection (.pvd).
#pragma once

#include "io/fields.hpp"

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace vitrum {

/// Writes n particles as VTK_VERTEX cells: points from `positions` (3n, interleaved), a point-data array
/// "radius" (n) and one point-data array per field (n x components). Binary appended data, zlib
/// compressed. In ParaView show it with Glyph (Sphere, scale by "radius", scale factor 2: radius ->
/// diameter). Throws RuntimeFailure naming `path` on bad field views or when the file cannot be written.
void writeParticlesVtu(const std::string& path, std::size_t n, const double* positions, const double* radius,
                       std::span<const FieldView> fields);

/// Writes the .pvtu index of a particle map cut into pieces (one .vtu per MPI rank, each as writeParticlesVtu
/// writes it, `pieces` relative to the .pvtu's directory): the points, "radius" and `fields` (name and
/// component count; the values are in the pieces). Atomic (temporary and rename). ParaView opens it as one
/// dataset.
void writeParticlesPvtu(const std::string& path, const std::vector<std::string>& pieces,
                        std::span<const FieldView> fields);

/// Writes bonds as VTK_LINE cells between particles i[b] and j[b] over all n_particles points, with one
/// cell-data array per bond field (n_bonds x components). Throws RuntimeFailure naming `path` on an index
/// out of range, bad field views or a failed write.
void writeBondsVtu(const std::string& path, std::size_t n_particles, const double* positions,
                   std::size_t n_bonds, const std::int32_t* i, const std::int32_t* j,
                   std::span<const FieldView> bond_fields);

/// Writes a tetrahedral mesh (the CNEM continuum of effect coupling: its domain tetrahedra) as VTK_TETRA
/// cells over n_points points with one point-data array per field (n_points x components; a 6-component
/// array is a symmetric tensor XX YY ZZ XY YZ XZ in ParaView). Throws RuntimeFailure naming `path` on an
/// index out of range, bad field views or a failed write.
void writeTetsVtu(const std::string& path, std::size_t n_points, const double* positions, std::size_t n_tets,
                  const std::int32_t* tets, std::span<const FieldView> point_fields);

/// The .pvd index ParaView opens to play the snapshots as a time series. write() rewrites the whole file
/// (through a temporary and a rename) so the collection is valid after every snapshot, even if the run dies.
class PvdCollection {
public:
    explicit PvdCollection(std::string path);
    /// Continues the collection at `path` after a restart at time `through_time` (ns): its entries up to that
    /// time are kept, later ones dropped. A missing file starts afresh.
    static PvdCollection continuing(std::string path, double through_time);
    /// `relative_file` is relative to the directory of the .pvd file.
    void add(double time, const std::string& relative_file);
    void write() const;

private:
    std::string path_;
    std::vector<std::pair<double, std::string>> entries_;
};

} // namespace vitrum
