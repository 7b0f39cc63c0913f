#include "io/vtk_writer.hpp"

#include "io/atomic_file.hpp"

#include "solver/errors.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkErrorCode.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <algorithm>
#include <charconv>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace vitrum {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
    throw RuntimeFailure("cannot write '" + path + "': " + what);
}

// VTK arrays own their storage, so the views are copied once here; the writer never keeps a pointer.
vtkNew<vtkDoubleArray> toVtkArray(const std::string& path, const FieldView& field, std::size_t count) {
    if (field.name.empty() || field.components < 1 || (count > 0 && field.data == nullptr))
        fail(path, "field '" + field.name + "' has no name, no components or no data");
    vtkNew<vtkDoubleArray> array;
    array->SetName(field.name.c_str());
    array->SetNumberOfComponents(field.components);
    array->SetNumberOfTuples(static_cast<vtkIdType>(count));
    std::copy_n(field.data, count * static_cast<std::size_t>(field.components), array->GetPointer(0));
    return array;
}

vtkNew<vtkPoints> toVtkPoints(const std::string& path, std::size_t n, const double* positions) {
    if (n > 0 && positions == nullptr)
        fail(path, "no positions");
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble(); // keep full precision: maps are compared against the solver state
    points->SetData(toVtkArray(path, FieldView{"Points", 3, positions}, n));
    return points;
}

void writeGrid(const std::string& path, vtkUnstructuredGrid* grid) {
    // Written beside the target and renamed over it: a reader (or a run killed mid-write) never leaves a
    // half-written map under the final name.
    const std::string temporary = path + ".tmp";
    vtkNew<vtkXMLUnstructuredGridWriter> writer;
    writer->SetFileName(temporary.c_str());
    writer->SetInputData(grid);
    writer->SetDataModeToAppended();
    writer->EncodeAppendedDataOff(); // raw binary rather than base64: a quarter smaller, ParaView reads both
    writer->SetCompressorTypeToZLib();
    writer->SetHeaderTypeToUInt64(); // 32-bit block headers overflow beyond 4 GiB of raw array data
    if (writer->Write() == 1 && writer->GetErrorCode() == vtkErrorCode::NoError) {
        std::error_code error;
        std::filesystem::rename(temporary, path, error);
        if (!error)
            return;
        std::filesystem::remove(temporary, error);
        fail(path, "cannot rename the written temporary file onto it");
    }
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    // Codes below FirstVTKErrorCode are errno values. The enum is header-only; its string table lives in
    // CommonMisc, which vitrum does not link, so the few codes a writer sets are named here.
    const unsigned long code = writer->GetErrorCode();
    if (code != vtkErrorCode::NoError && code < vtkErrorCode::FirstVTKErrorCode)
        fail(path, std::strerror(static_cast<int>(code)));
    if (code == vtkErrorCode::OutOfDiskSpaceError)
        fail(path, "out of disk space");
    fail(path, "VTK writer failed (error code " + std::to_string(code) + ")");
}

} // namespace

void writeParticlesVtu(const std::string& path, std::size_t n, const double* positions, const double* radius,
                       std::span<const FieldView> fields) {
    vtkNew<vtkUnstructuredGrid> grid;
    grid->SetPoints(toVtkPoints(path, n, positions));

    // One vertex per particle: connectivity 0..n-1 with a fixed cell size of 1.
    vtkNew<vtkIdTypeArray> connectivity;
    connectivity->SetNumberOfTuples(static_cast<vtkIdType>(n));
    for (std::size_t p = 0; p < n; ++p)
        connectivity->SetValue(static_cast<vtkIdType>(p), static_cast<vtkIdType>(p));
    vtkNew<vtkCellArray> cells;
    if (!cells->SetData(1, connectivity))
        fail(path, "cannot build vertex cells");
    grid->SetCells(VTK_VERTEX, cells);

    vtkPointData* point_data = grid->GetPointData();
    point_data->AddArray(toVtkArray(path, FieldView{"radius", 1, radius}, n));
    for (const FieldView& field : fields) {
        if (point_data->HasArray(field.name.c_str()))
            fail(path, "duplicate field name '" + field.name + "'");
        point_data->AddArray(toVtkArray(path, field, n));
    }
    point_data->SetActiveScalars("radius"); // so ParaView's Glyph offers it first as the scale array
    writeGrid(path, grid);
}

void writeParticlesPvtu(const std::string& path, const std::vector<std::string>& pieces,
                        std::span<const FieldView> fields) {
    std::ostringstream x;
    x << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      << "  <PUnstructuredGrid GhostLevel=\"0\">\n"
      << "    <PPointData Scalars=\"radius\">\n"
      << "      <PDataArray type=\"Float64\" Name=\"radius\" NumberOfComponents=\"1\"/>\n";
    for (const FieldView& f : fields) {
        x << "      <PDataArray type=\"Float64\" Name=\"" << f.name << "\" NumberOfComponents=\"" << f.components
          << "\"/>\n";
    }
    x << "    </PPointData>\n"
      << "    <PPoints>\n      <PDataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"/>\n    </PPoints>\n";
    for (const std::string& piece : pieces) {
        x << "    <Piece Source=\"" << piece << "\"/>\n";
    }
    x << "  </PUnstructuredGrid>\n</VTKFile>\n";
    try {
        writeFileAtomically(path, x.str());
    } catch (const std::exception& e) {
        fail(path, e.what());
    }
}

void writeBondsVtu(const std::string& path, std::size_t n_particles, const double* positions,
                   std::size_t n_bonds, const std::int32_t* i, const std::int32_t* j,
                   std::span<const FieldView> bond_fields) {
    if (n_bonds > 0 && (i == nullptr || j == nullptr))
        fail(path, "no bond indices");
    vtkNew<vtkUnstructuredGrid> grid;
    grid->SetPoints(toVtkPoints(path, n_particles, positions));

    vtkNew<vtkIdTypeArray> connectivity;
    connectivity->SetNumberOfTuples(static_cast<vtkIdType>(2 * n_bonds));
    for (std::size_t b = 0; b < n_bonds; ++b) {
        for (int end = 0; end < 2; ++end) {
            const std::int32_t p = end == 0 ? i[b] : j[b];
            if (p < 0 || static_cast<std::size_t>(p) >= n_particles)
                fail(path, "bond " + std::to_string(b) + " refers to particle " + std::to_string(p) + " of " +
                               std::to_string(n_particles));
            connectivity->SetValue(static_cast<vtkIdType>(2 * b + end), p);
        }
    }
    vtkNew<vtkCellArray> cells;
    if (!cells->SetData(2, connectivity))
        fail(path, "cannot build line cells");
    grid->SetCells(VTK_LINE, cells);

    vtkCellData* cell_data = grid->GetCellData();
    for (const FieldView& field : bond_fields) {
        if (cell_data->HasArray(field.name.c_str()))
            fail(path, "duplicate field name '" + field.name + "'");
        cell_data->AddArray(toVtkArray(path, field, n_bonds));
    }
    writeGrid(path, grid);
}

void writeTetsVtu(const std::string& path, std::size_t n_points, const double* positions, std::size_t n_tets,
                  const std::int32_t* tets, std::span<const FieldView> point_fields) {
    if (n_tets > 0 && tets == nullptr)
        fail(path, "no tetrahedra");
    vtkNew<vtkUnstructuredGrid> grid;
    grid->SetPoints(toVtkPoints(path, n_points, positions));
    vtkNew<vtkIdTypeArray> connectivity;
    connectivity->SetNumberOfTuples(static_cast<vtkIdType>(4 * n_tets));
    for (std::size_t k = 0; k < 4 * n_tets; ++k) {
        if (tets[k] < 0 || static_cast<std::size_t>(tets[k]) >= n_points)
            fail(path, "tetrahedron " + std::to_string(k / 4) + " refers to node " + std::to_string(tets[k]) +
                           " of " + std::to_string(n_points));
        connectivity->SetValue(static_cast<vtkIdType>(k), tets[k]);
    }
    vtkNew<vtkCellArray> cells;
    if (!cells->SetData(4, connectivity))
        fail(path, "cannot build tetrahedral cells");
    grid->SetCells(VTK_TETRA, cells);
    vtkPointData* point_data = grid->GetPointData();
    for (const FieldView& field : point_fields) {
        if (point_data->HasArray(field.name.c_str()))
            fail(path, "duplicate field name '" + field.name + "'");
        point_data->AddArray(toVtkArray(path, field, n_points));
    }
    writeGrid(path, grid);
}

PvdCollection::PvdCollection(std::string path) : path_(std::move(path)) {}

PvdCollection PvdCollection::continuing(std::string path, double through_time) {
    PvdCollection pvd(path);
    std::ifstream in(path);
    std::string line;
    // The entries write() writes, one per line: <DataSet timestep="T" group="" part="0" file="F"/>.
    while (std::getline(in, line)) {
        const std::size_t t = line.find("timestep=\"");
        const std::size_t f = line.find("file=\"");
        if (t == std::string::npos || f == std::string::npos) {
            continue;
        }
        const double time = std::strtod(line.c_str() + t + 10, nullptr);
        const std::size_t end = line.find('"', f + 6);
        if (end == std::string::npos || time > through_time) {
            continue;
        }
        std::string file = line.substr(f + 6, end - f - 6);
        for (const auto& [escaped, plain] : {std::pair<std::string, std::string>{"&quot;", "\""}, {"&lt;", "<"},
                                             {"&gt;", ">"}, {"&amp;", "&"}}) {
            for (std::size_t at = file.find(escaped); at != std::string::npos; at = file.find(escaped, at + 1)) {
                file.replace(at, escaped.size(), plain);
            }
        }
        pvd.add(time, file);
    }
    return pvd;
}

void PvdCollection::add(double time, const std::string& relative_file) {
    entries_.emplace_back(time, relative_file);
}

void PvdCollection::write() const {
    auto escaped = [](const std::string& text) {
        std::string out;
        for (char c : text) {
            switch (c) {
            case '&':
                out += "&amp;";
                break;
            case '<':
                out += "&lt;";
                break;
            case '>':
                out += "&gt;";
                break;
            case '"':
                out += "&quot;";
                break;
            default:
                out += c;
            }
        }
        return out;
    };
    // Write beside the target and rename over it, so a reader never sees a half-written index.
    const std::string temporary = path_ + ".tmp";
    {
        std::ofstream out(temporary, std::ios::trunc);
        if (!out)
            fail(path_, "cannot open '" + temporary + "'");
        out << "<?xml version=\"1.0\"?>\n"
               "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
               "  <Collection>\n";
        char time_text[32];
        for (const auto& [time, file] : entries_) {
            // Shortest text that reads back as the same double, so time steps stay exact and legible.
            *std::to_chars(time_text, time_text + sizeof time_text - 1, time).ptr = '\0';
            out << "    <DataSet timestep=\"" << time_text << "\" group=\"\" part=\"0\" file=\""
                << escaped(file) << "\"/>\n";
        }
        out << "  </Collection>\n</VTKFile>\n";
        out.close();
        if (!out)
            fail(path_, "write to '" + temporary + "' failed");
    }
    std::error_code error;
    std::filesystem::rename(temporary, path_, error);
    if (error)
        fail(path_, error.message());
}

} // namespace vitrum
