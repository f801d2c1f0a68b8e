// SPDX-License-Identifier: MIT
// Triangulated walls of the scene ("type": "mesh"): a 3D surface from an STL file (ASCII or
// binary, its orientation kept: normals into the free side) or a 2D polyline given inline. The
// surface is checked (model::check_wall_mesh: sizes, finite coordinates, degenerate cells,
// orientation) and shared by the wall; its bounding-box centre is the wall's point.
#include "model/wall_mesh.hpp"

#include "core/errors.hpp"
#include "core/files.hpp"
#include "pipeline/scene/build.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace pd::pipeline::scene {

namespace {

/// An STL file's triangles as a soup (9 coordinates per triangle).
std::vector<double> read_stl_soup(const std::string& path, const std::string& key) {
    note_input("STL file", path);
    std::error_code ec;
    const auto size = std::filesystem::file_size(path, ec);
    std::ifstream in(path, std::ios::binary);
    if (ec || !in || !std::filesystem::is_regular_file(path))
        throw ConfigError(key, fmt::format("cannot open STL file '{}'", path));
    const std::uintmax_t limit = 84 + 50 * static_cast<std::uintmax_t>(model::max_wall_mesh_cells);
    if (size > 8 * limit)
        throw ConfigError(key, fmt::format("'{}' has {} bytes: too large for a wall of at most {} "
                                           "triangles",
                                           path, size, model::max_wall_mesh_cells));
    std::string bytes(static_cast<std::size_t>(size), '\0');
    in.read(bytes.data(), static_cast<std::streamsize>(size));
    std::vector<double> soup;
    std::uint32_t n = 0;
    if (size >= 84)
        std::memcpy(&n, bytes.data() + 80, 4);
    if (size >= 84 && size == 84 + 50 * static_cast<std::uintmax_t>(n)) { // binary
        if (n > model::max_wall_mesh_cells)
            throw ConfigError(key, fmt::format("'{}' has {} triangles, more than the {} a wall "
                                               "may have",
                                               path, n, model::max_wall_mesh_cells));
        for (std::uint32_t t = 0; t < n; ++t)
            for (int k = 0; k < 9; ++k) {
                float x = 0;
                std::memcpy(&x, bytes.data() + 84 + 50 * t + 12 + 4 * k, 4);
                soup.push_back(static_cast<double>(x));
            }
        return soup;
    }
    std::istringstream text(bytes);
    std::string word;
    text >> word;
    if (word != "solid")
        throw ConfigError(key, fmt::format("'{}' is not an STL file (neither binary of the size "
                                           "its triangle count gives nor ASCII 'solid ...')",
                                           path));
    while (text >> word) {
        if (word != "vertex")
            continue;
        double x[3];
        if (!(text >> x[0] >> x[1] >> x[2]))
            throw ConfigError(key, fmt::format("'{}': a vertex without three numbers", path));
        soup.insert(soup.end(), x, x + 3);
        if (soup.size() > 9 * model::max_wall_mesh_cells)
            throw ConfigError(key, fmt::format("'{}' has more than the {} triangles a wall may "
                                               "have",
                                               path, model::max_wall_mesh_cells));
    }
    if (soup.size() % 9 != 0)
        throw ConfigError(key,
                          fmt::format("'{}': {} vertices, not 3 per facet", path, soup.size() / 3));
    return soup;
}

/// A 2D polyline: points and segments (closed: back to the first point).
void read_polyline(const json& wj, const std::string& w, std::vector<double>& points,
                   std::vector<std::int32_t>& cells) {
    const auto& pl = wj.at("polyline");
    if (!pl.is_array() || pl.size() < 2 || pl.size() > model::max_wall_mesh_cells)
        throw ConfigError(w + ".polyline", fmt::format("expected 2 to {} points [x, y]",
                                                       model::max_wall_mesh_cells));
    for (std::size_t i = 0; i < pl.size(); ++i) {
        const auto& p = pl[i];
        if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number())
            throw ConfigError(fmt::format("{}.polyline[{}]", w, i), "expected [x, y]");
        points.insert(points.end(), {p[0].get<double>(), p[1].get<double>(), 0.0});
    }
    const bool closed = wj.value("closed", false);
    const auto np = static_cast<std::int32_t>(pl.size());
    for (std::int32_t i = 0; i + 1 < np + (closed ? 1 : 0); ++i)
        cells.insert(cells.end(), {i, (i + 1) % np});
}

} // namespace

void parse_wall_mesh(const json& wj, const std::string& w, model::Wall& wall, int dim,
                     const Folder& base) {
    std::vector<double> points;
    std::vector<std::int32_t> cells;
    std::string what;
    if (dim == 3) {
        if (!wj.contains("file") || wj.contains("polyline"))
            throw ConfigError(w + ".file", "a 3D mesh wall reads its triangles from an STL file "
                                           "(ASCII or binary), relative to the scene file");
        const auto file = text(wj, w, "file", "");
        const auto path = resolve(base, file, w + ".file");
        model::weld_triangles(read_stl_soup(path, w + ".file"), points, cells);
        what = fmt::format("{}.file ('{}')", w, file);
    } else {
        if (!wj.contains("polyline") || wj.contains("file"))
            throw ConfigError(w + ".polyline", "a 2D mesh wall is a polyline: [[x, y], ...]");
        read_polyline(wj, w, points, cells);
        what = w + ".polyline";
    }
    if (wj.value("flip", false)) // the other side is the free side
        for (std::size_t c = 0; c < cells.size(); c += static_cast<std::size_t>(dim))
            std::swap(cells[c], cells[c + 1]);
    const auto why = model::check_wall_mesh(dim, points, cells);
    if (!why.empty())
        throw ConfigError(what, why);
    std::array<double, 3> lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (std::size_t i = 0; i < points.size(); ++i) {
        lo[i % 3] = std::min(lo[i % 3], points[i]);
        hi[i % 3] = std::max(hi[i % 3], points[i]);
    }
    for (std::size_t k = 0; k < 3; ++k)
        wall.point[k] = 0.5 * (lo[k] + hi[k]);
    wall.mesh = std::make_shared<const model::WallMesh>(dim, std::move(points), std::move(cells));
}

} // namespace pd::pipeline::scene
