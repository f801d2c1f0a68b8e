// SPDX-License-Identifier: MIT
// XDMF 2 sidecar writer (see xdmf.hpp). Plain XML; the heavy data stays in the HDF5 file.
#include "post/xdmf.hpp"

#include "core/errors.hpp"
#include "h5/file.hpp"
#include "post/text_out.hpp"
#include "post/vtk_export_walls.hpp"
#include "store/frames.hpp"
#include "store/schema.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <type_traits>
#include <vector>

namespace pd::post {

namespace {

/// A HyperSlab DataItem selecting frame k of a (T, N[, 3]) dataset.
std::string hyperslab(std::size_t k, std::size_t frames, std::size_t n, int components,
                      const std::string& h5_ref, const std::string& dataset) {
    const bool vec = components > 1;
    const std::string dims = vec ? fmt::format("1 {} {}", n, components) : fmt::format("1 {}", n);
    const std::string all =
        vec ? fmt::format("{} {} {}", frames, n, components) : fmt::format("{} {}", frames, n);
    const std::string select = vec ? fmt::format("{} 0 0 1 1 1 1 {} {}", k, n, components)
                                   : fmt::format("{} 0 1 1 1 {}", k, n);
    return fmt::format(
        "        <DataItem ItemType=\"HyperSlab\" Dimensions=\"{}\" Type=\"HyperSlab\">\n"
        "          <DataItem Dimensions=\"3 {}\" Format=\"XML\">{}</DataItem>\n"
        "          <DataItem Dimensions=\"{}\" NumberType=\"Float\" Precision=\"8\" "
        "Format=\"HDF\">{}:{}</DataItem>\n"
        "        </DataItem>\n",
        dims, vec ? 3 : 2, select, all, xml_escape(h5_ref), dataset);
}

/// `values` as the text of an inline XML DataItem, `per_line` to a line.
template <class T>
std::string inline_values(const std::vector<T>& values, std::size_t per_line) {
    std::string s;
    for (std::size_t i = 0; i < values.size(); ++i) {
        if (i % per_line == 0)
            s += "\n          ";
        else
            s += ' ';
        if constexpr (std::is_floating_point_v<T>)
            s += fmt::format("{:.17g}", values[i]);
        else
            s += fmt::format("{}", values[i]);
    }
    return s + "\n        ";
}

/// The rigid walls at time t as one Uniform grid with inline data.
std::string wall_grid(const model::Model& m, const WallExtent& extent, std::size_t k, double t) {
    const auto o = wall_outline(m.walls, m.dimension, extent, t);
    const std::size_t nc = o.num_cells(), np = o.num_points();
    const int pc = o.points_per_cell;
    return fmt::format(
        "    <Grid Name=\"walls_{}\" GridType=\"Uniform\">\n"
        "      <Time Value=\"{:.17g}\"/>\n"
        "      <Topology TopologyType=\"{}\" NumberOfElements=\"{}\"{}>\n"
        "        <DataItem Dimensions=\"{} {}\" NumberType=\"Int\" Precision=\"8\" "
        "Format=\"XML\">{}</DataItem>\n"
        "      </Topology>\n"
        "      <Geometry GeometryType=\"XYZ\">\n"
        "        <DataItem Dimensions=\"{} 3\" NumberType=\"Float\" Precision=\"8\" "
        "Format=\"XML\">{}</DataItem>\n"
        "      </Geometry>\n"
        "      <Attribute Name=\"wall\" AttributeType=\"Scalar\" Center=\"Cell\">\n"
        "        <DataItem Dimensions=\"{}\" NumberType=\"Int\" Precision=\"4\" "
        "Format=\"XML\">{}</DataItem>\n"
        "      </Attribute>\n"
        "      <Attribute Name=\"velocity\" AttributeType=\"Vector\" Center=\"Node\">\n"
        "        <DataItem Dimensions=\"{} 3\" NumberType=\"Float\" Precision=\"8\" "
        "Format=\"XML\">{}</DataItem>\n"
        "      </Attribute>\n"
        "    </Grid>\n",
        k, t, pc == 4 ? "Quadrilateral" : "Polyline", nc, pc == 4 ? "" : " NodesPerElement=\"2\"",
        nc, pc, inline_values(o.cells, static_cast<std::size_t>(pc) * 8), np,
        inline_values(o.points, 3), nc, inline_values(o.wall, 16), np,
        inline_values(o.velocity, 3));
}

} // namespace

std::size_t write_xdmf(const h5::File& f, const std::string& xmf_path, const std::string& h5_ref,
                       const model::Model* m) {
    store::FrameReader frames(f);
    const std::string particles = store::path::particles;
    const auto fields = frames.fields();
    if (std::find(fields.begin(), fields.end(), "position") == fields.end())
        throw SchemaError(f.name(), particles + "/position", "missing (no positions for XDMF)");
    const std::size_t n = frames.num_nodes(), t = frames.num_frames();
    const std::string nodes = store::path::nodes;
    const bool has_body = f.exists(nodes + "/body"), has_volume = f.exists(nodes + "/volume");

    auto out = open_output(xmf_path);
    // Written frame by frame: the text does not accumulate in memory.
    const auto put = [&](const std::string& text) {
        if (std::fputs(text.c_str(), out.get()) < 0)
            throw InputError(fmt::format("{}: write failed (disk full?)", xmf_path));
    };
    std::string s =
        "<?xml version=\"1.0\" ?>\n"
        "<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
        "<Xdmf Version=\"2.0\">\n  <Domain>\n"
        "    <Grid Name=\"nodes\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    put(s);
    for (std::size_t k = 0; k < t; ++k) {
        s = fmt::format("    <Grid Name=\"frame_{}\" GridType=\"Uniform\">\n"
                        "      <Time Value=\"{:.17g}\"/>\n"
                        "      <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{}\" "
                        "NodesPerElement=\"1\"/>\n"
                        "      <Geometry GeometryType=\"XYZ\">\n",
                        k, frames.time(k), n);
        s += hyperslab(k, t, n, 3, h5_ref, particles + "/position/value");
        s += "      </Geometry>\n";
        for (const auto& name : fields) {
            const int c = frames.components(name);
            s += fmt::format("      <Attribute Name=\"{}\" AttributeType=\"{}\" Center=\"Node\">\n",
                             name, c == 1 ? "Scalar" : "Vector");
            s += hyperslab(k, t, n, c, h5_ref, particles + "/" + name + "/value");
            s += "      </Attribute>\n";
        }
        if (has_body)
            s += fmt::format("      <Attribute Name=\"body\" AttributeType=\"Scalar\" "
                             "Center=\"Node\">\n        <DataItem Dimensions=\"{}\" "
                             "NumberType=\"Int\" Precision=\"4\" Format=\"HDF\">{}:{}/body"
                             "</DataItem>\n      </Attribute>\n",
                             n, xml_escape(h5_ref), nodes);
        if (has_volume)
            s += fmt::format("      <Attribute Name=\"volume\" AttributeType=\"Scalar\" "
                             "Center=\"Node\">\n        <DataItem Dimensions=\"{}\" "
                             "NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">{}:{}/volume"
                             "</DataItem>\n      </Attribute>\n",
                             n, xml_escape(h5_ref), nodes);
        s += "    </Grid>\n";
        put(s);
    }
    put("    </Grid>\n");
    if (m && !m->walls.empty()) {
        const auto extent = wall_extent(m->nodes);
        put("    <Grid Name=\"walls\" GridType=\"Collection\" CollectionType=\"Temporal\">\n");
        for (std::size_t k = 0; k < t; ++k)
            put(wall_grid(*m, extent, k, frames.time(k)));
        put("    </Grid>\n");
    }
    put("  </Domain>\n</Xdmf>\n");
    if (std::fflush(out.get()) != 0)
        throw InputError(fmt::format("{}: write failed (disk full?)", xmf_path));
    return t;
}

} // namespace pd::post
