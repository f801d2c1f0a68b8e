// SPDX-License-Identifier: MIT
// VTU + PVD writer (see vtk_export.hpp). The only VTK code of pdgrain: XML writers only.
// Format: appended raw binary, zlib-compressed; the PVD is written by hand (plain XML).
#include "post/vtk_export.hpp"

#include "core/errors.hpp"
#include "core/files.hpp"
#include "h5/file.hpp"
#include "post/text_out.hpp"
#include "post/vtk_export_walls.hpp"
#include "store/frames.hpp"
#include "store/schema.hpp"

#include <fmt/format.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkErrorCode.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <unistd.h>
#include <vector>

namespace pd::post {

namespace {

/// Writes `path` under a temporary name and renames it when complete, so that a killed or failing
/// pd-post leaves no truncated frame under the real name. VTK's Write() returns 1 on a full disk
/// (measured: a 0-byte .vtu), so its error code and the written size are checked as well.
void write_vtu(vtkXMLUnstructuredGridWriter& writer, const std::string& path) {
    const std::string tmp = path + ".tmp";
    // Created here exclusively (a link planted under the name is removed, never followed); VTK
    // then writes into this regular file.
    if (const int fd = create_side_file(tmp); fd >= 0)
        ::close(fd);
    else
        throw InputError(fmt::format("{}: cannot create {}: {}", path, tmp, std::strerror(errno)));
    writer.SetFileName(tmp.c_str());
    std::error_code ec;
    const bool ok = writer.Write() == 1 && writer.GetErrorCode() == vtkErrorCode::NoError &&
                    std::filesystem::file_size(tmp, ec) > 0 && !ec;
    if (!ok || std::rename(tmp.c_str(), path.c_str()) != 0) {
        std::remove(tmp.c_str());
        throw InputError(fmt::format("{}: cannot write (VTK XML writer failed; disk full?)", path));
    }
}

/// One VTK_VERTEX cell per point.
void set_vertex_cells(vtkUnstructuredGrid* grid, vtkIdType n) {
    vtkNew<vtkIdTypeArray> offsets;
    vtkNew<vtkIdTypeArray> connectivity;
    offsets->SetNumberOfValues(n + 1);
    connectivity->SetNumberOfValues(n);
    for (vtkIdType i = 0; i < n; ++i) {
        offsets->SetValue(i, i);
        connectivity->SetValue(i, i);
    }
    offsets->SetValue(n, n);
    vtkNew<vtkCellArray> cells;
    cells->SetData(offsets, connectivity);
    grid->SetCells(VTK_VERTEX, cells);
}

/// One VTK_VERTEX cell per point (meshio rejects a .vtu without cells, environment notes B.5),
/// then the grains' boundary facets: VTK_LINE (2D) or VTK_TRIANGLE (3D) cells.
void set_cells(vtkUnstructuredGrid* grid, vtkIdType n, const GrainOutline& outline) {
    if (outline.cells.empty())
        return set_vertex_cells(grid, n);
    vtkNew<vtkCellArray> cells;
    vtkNew<vtkUnsignedCharArray> types;
    for (vtkIdType i = 0; i < n; ++i) {
        cells->InsertNextCell(1, &i);
        types->InsertNextValue(VTK_VERTEX);
    }
    const int ppc = outline.points_per_cell;
    for (std::size_t c = 0; c < outline.num_cells(); ++c) {
        vtkIdType ids[3];
        for (int q = 0; q < ppc; ++q)
            ids[q] = static_cast<vtkIdType>(
                outline.cells[c * static_cast<std::size_t>(ppc) + static_cast<std::size_t>(q)]);
        cells->InsertNextCell(ppc, ids);
        types->InsertNextValue(ppc == 2 ? VTK_LINE : VTK_TRIANGLE);
    }
    grid->SetCells(types, cells);
}

void write_pvd(const std::string& path, const std::vector<std::pair<double, std::string>>& items) {
    auto out = open_output(path);
    std::string s = "<?xml version=\"1.0\"?>\n"
                    "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
                    "  <Collection>\n";
    for (const auto& [time, file] : items)
        s += fmt::format("    <DataSet timestep=\"{:.17g}\" group=\"\" part=\"0\" file=\"{}\"/>\n",
                         time, xml_escape(file));
    s += "  </Collection>\n</VTKFile>\n";
    if (std::fputs(s.c_str(), out.get()) < 0 || std::fflush(out.get()) != 0)
        throw InputError(fmt::format("{}: write failed (disk full?)", path));
}

/// Removes `<stem>_<k:06>.vtu` for k = first, first + 1, ... while they exist: frames beyond the
/// last one, left by an earlier export of a longer run, would join the series in ParaView's file
/// grouping.
void remove_stale_tail(const std::string& out_dir, const std::string& stem, std::size_t first) {
    for (std::size_t k = first;; ++k) {
        const auto stale = std::filesystem::path(out_dir) / fmt::format("{}_{:06d}.vtu", stem, k);
        std::error_code ec;
        if (!std::filesystem::remove(stale, ec))
            break;
    }
}

} // namespace

VtuSeries write_vtu_series(const h5::File& f, const model::Nodes& nodes, const std::string& out_dir,
                           const std::string& stem, const Progress& progress,
                           const GrainOutline& outline) {
    store::FrameReader frames(f);
    const std::string particles = store::path::particles;
    const auto n = frames.num_nodes();
    if (n != nodes.num())
        throw SchemaError(
            f.name(), particles + "/position/value",
            fmt::format("has {} nodes per frame, expected {} (/nodes)", n, nodes.num()));
    const auto fields = frames.fields();
    if (std::find(fields.begin(), fields.end(), "position") == fields.end())
        throw SchemaError(f.name(), particles + "/position", "missing (no positions to plot)");

    vtkNew<vtkUnstructuredGrid> grid;
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    points->SetNumberOfPoints(static_cast<vtkIdType>(n));
    grid->SetPoints(points);
    set_cells(grid, static_cast<vtkIdType>(n), outline);

    vtkNew<vtkIntArray> body;
    body->SetName("body");
    body->SetNumberOfValues(static_cast<vtkIdType>(n));
    std::copy(nodes.body.begin(), nodes.body.end(), body->GetPointer(0));
    grid->GetPointData()->AddArray(body);
    vtkNew<vtkDoubleArray> volume;
    volume->SetName("volume");
    volume->SetNumberOfValues(static_cast<vtkIdType>(n));
    std::copy(nodes.volume.begin(), nodes.volume.end(), volume->GetPointer(0));
    grid->GetPointData()->AddArray(volume);

    std::vector<vtkSmartPointer<vtkDoubleArray>> arrays;
    for (const auto& name : fields) {
        auto a = vtkSmartPointer<vtkDoubleArray>::New();
        a->SetName(name.c_str());
        a->SetNumberOfComponents(frames.components(name));
        a->SetNumberOfTuples(static_cast<vtkIdType>(n));
        grid->GetPointData()->AddArray(a);
        arrays.push_back(a);
    }

    vtkNew<vtkXMLUnstructuredGridWriter> writer;
    writer->SetInputData(grid);
    writer->SetDataModeToAppended();
    writer->EncodeAppendedDataOff();
    writer->SetCompressorTypeToZLib();

    std::vector<std::pair<double, std::string>> listed;
    for (std::size_t k = 0; k < frames.num_frames(); ++k) {
        for (std::size_t i = 0; i < fields.size(); ++i) {
            const auto values = frames.read(fields[i], k);
            const auto want = n * static_cast<std::size_t>(frames.components(fields[i]));
            if (values.size() != want)
                throw SchemaError(
                    f.name(), particles + "/" + fields[i] + "/value",
                    fmt::format("frame {} has {} values, expected {}", k, values.size(), want));
            std::copy(values.begin(), values.end(), arrays[i]->GetPointer(0));
            arrays[i]->Modified();
            if (fields[i] == "position") {
                for (std::size_t p = 0; p < n; ++p)
                    points->SetPoint(static_cast<vtkIdType>(p), values.data() + 3 * p);
                points->Modified();
            }
        }
        const std::string name = fmt::format("{}_{:06d}.vtu", stem, k);
        const std::string path = (std::filesystem::path(out_dir) / name).string();
        write_vtu(*writer, path);
        listed.emplace_back(frames.time(k), name);
        if (progress)
            progress("vtu", k + 1, frames.num_frames());
    }
    remove_stale_tail(out_dir, stem, listed.size());
    VtuSeries out;
    out.frames = listed.size();
    out.pvd = (std::filesystem::path(out_dir) / (stem + ".pvd")).string();
    write_pvd(out.pvd, listed);
    return out;
}

VtuSeries write_wall_series(const h5::File& f, const model::Model& m, const std::string& out_dir,
                            const std::string& stem) {
    VtuSeries out;
    if (m.walls.empty())
        return out;
    store::FrameReader frames(f);
    const auto extent = wall_extent(m.nodes);
    const std::string wstem = stem + "_walls";
    vtkNew<vtkXMLUnstructuredGridWriter> writer;
    writer->SetDataModeToAppended();
    writer->EncodeAppendedDataOff();
    writer->SetCompressorTypeToZLib();
    std::vector<std::pair<double, std::string>> listed;
    for (std::size_t k = 0; k < frames.num_frames(); ++k) {
        const auto o = wall_outline(m.walls, m.dimension, extent, frames.time(k));
        const auto np = static_cast<vtkIdType>(o.num_points());
        const auto nc = static_cast<vtkIdType>(o.num_cells());
        vtkNew<vtkUnstructuredGrid> grid;
        vtkNew<vtkPoints> points;
        points->SetDataTypeToDouble();
        points->SetNumberOfPoints(np);
        for (vtkIdType i = 0; i < np; ++i)
            points->SetPoint(i, o.points.data() + 3 * i);
        grid->SetPoints(points);
        vtkNew<vtkIdTypeArray> offsets;
        vtkNew<vtkIdTypeArray> connectivity;
        offsets->SetNumberOfValues(nc + 1);
        for (vtkIdType c = 0; c <= nc; ++c)
            offsets->SetValue(c, c * o.points_per_cell);
        connectivity->SetNumberOfValues(static_cast<vtkIdType>(o.cells.size()));
        for (std::size_t i = 0; i < o.cells.size(); ++i)
            connectivity->SetValue(static_cast<vtkIdType>(i), o.cells[i]);
        vtkNew<vtkCellArray> cells;
        cells->SetData(offsets, connectivity);
        grid->SetCells(o.points_per_cell == 4 ? VTK_QUAD : VTK_LINE, cells);
        vtkNew<vtkIntArray> wall;
        wall->SetName("wall");
        wall->SetNumberOfValues(nc);
        std::copy(o.wall.begin(), o.wall.end(), wall->GetPointer(0));
        grid->GetCellData()->AddArray(wall);
        vtkNew<vtkDoubleArray> velocity;
        velocity->SetName("velocity");
        velocity->SetNumberOfComponents(3);
        velocity->SetNumberOfTuples(np);
        std::copy(o.velocity.begin(), o.velocity.end(), velocity->GetPointer(0));
        grid->GetPointData()->AddArray(velocity);

        const std::string name = fmt::format("{}_{:06d}.vtu", wstem, k);
        const std::string path = (std::filesystem::path(out_dir) / name).string();
        writer->SetInputData(grid);
        write_vtu(*writer, path);
        listed.emplace_back(frames.time(k), name);
    }
    remove_stale_tail(out_dir, wstem, listed.size());
    out.frames = listed.size();
    out.pvd = (std::filesystem::path(out_dir) / (wstem + ".pvd")).string();
    write_pvd(out.pvd, listed);
    return out;
}

} // namespace pd::post
