// SPDX-License-Identifier: MIT
// fragments.csv and psd.csv writer (see fragments.hpp). Hardin's relative breakage (Hardin,
// J. Geotech. Eng. 111 (1985) 1177) on the mass-weighted grading: the breakage potential of a
// piece of equivalent diameter d is b_p = max(0, ln(d / d_cut)), so B_p = sum_k w_k b_p(d_k)
// (w_k mass fractions) is the area between the cumulative grading curve F(ln d) and F = 1 above
// the cut-off; B_t = B_p(first frame) - B_p(frame), B_r = B_t / B_p(first frame).
#include "post/fragments.hpp"

#include "core/errors.hpp"
#include "h5/file.hpp"
#include "post/text_out.hpp"
#include "store/frames.hpp"
#include "store/schema.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <vector>

namespace pd::post {

namespace {

/// One fragment (or the fines of a grain) at a frame: sums over its nodes.
struct Piece {
    std::int64_t id = 0; ///< smallest node index; -1 = the fines of the grain
    std::size_t body = 0;
    std::int64_t nodes = 0;
    double volume = 0, mass = 0;
    double mx[3] = {0, 0, 0}, mv[3] = {0, 0, 0};
};

/// Equivalent diameter of a volume (2D: of the area, volume per unit thickness).
double diameter(double volume, int dimension) {
    return dimension == 2 ? std::sqrt(4 * volume / std::numbers::pi)
                          : std::cbrt(6 * volume / std::numbers::pi);
}

/// The bodies whose fragments count: moving particles, not the meshed walls (the fixed or driven
/// bodies whose reactions the file records).
std::vector<std::size_t> counted_bodies(const h5::File& f, const model::Model& m) {
    const auto walls = store::read_reaction_bodies(f);
    std::vector<std::size_t> out;
    for (std::size_t b = 0; b + 1 < m.bodies.node_offsets.size(); ++b)
        if (m.bodies.kind[b] == model::BodyKind::particle && !m.bodies.fixed[b] &&
            std::find(walls.begin(), walls.end(), static_cast<std::int32_t>(b)) == walls.end())
            out.push_back(b);
    return out;
}

/// The pieces of the counted bodies at one frame: fragments (id order within each body, bodies
/// in order), each body's fines last in its run. `acc` is scratch of n pieces.
std::vector<Piece> pieces(const model::Model& m, const std::vector<std::size_t>& bodies,
                          const std::vector<double>& frag, const std::vector<double>& x,
                          const std::vector<double>& v, std::int64_t fines_nodes,
                          std::vector<Piece>& acc) {
    std::vector<Piece> out;
    for (const auto b : bodies) {
        const auto lo = m.bodies.node_offsets[b], hi = m.bodies.node_offsets[b + 1];
        const double rho = m.materials[static_cast<std::size_t>(m.bodies.material[b])].density;
        for (auto i = lo; i < hi; ++i)
            acc[static_cast<std::size_t>(i)] = Piece{};
        for (auto i = lo; i < hi; ++i) {
            const auto id = static_cast<std::int64_t>(frag[static_cast<std::size_t>(i)]);
            if (id < lo || id >= hi)
                throw InternalError(fmt::format("node {} of body {} has fragment id {} outside "
                                                "the body's nodes [{}, {})",
                                                i, b, id, lo, hi));
            Piece& p = acc[static_cast<std::size_t>(id)];
            const double vol = m.nodes.volume[static_cast<std::size_t>(i)];
            p.nodes += 1;
            p.volume += vol;
            p.mass += rho * vol;
            for (int d = 0; d < 3; ++d) {
                p.mx[d] += rho * vol * x[3 * static_cast<std::size_t>(i) + d];
                if (!v.empty())
                    p.mv[d] += rho * vol * v[3 * static_cast<std::size_t>(i) + d];
            }
        }
        Piece fines{-1, b};
        for (auto i = lo; i < hi; ++i) {
            Piece& p = acc[static_cast<std::size_t>(i)];
            if (p.nodes == 0)
                continue;
            p.id = i;
            p.body = b;
            if (p.nodes >= fines_nodes) {
                out.push_back(p);
                continue;
            }
            fines.nodes += p.nodes;
            fines.volume += p.volume;
            fines.mass += p.mass;
            for (int d = 0; d < 3; ++d) {
                fines.mx[d] += p.mx[d];
                fines.mv[d] += p.mv[d];
            }
            p.id = -2; // a fine: still a piece of the grading (psd), marked
        }
        if (fines.nodes > 0)
            out.push_back(fines);
    }
    return out;
}

/// One row of psd.csv.
struct Grading {
    std::int64_t fragments = 0, fines = 0;
    double fines_mass = 0, mass = 0, d10 = 0, d50 = 0, d90 = 0;
    double largest_mean = 0, largest_min = 0, bp = 0;
};

/// Mass-weighted percentile: the smallest d whose cumulative mass fraction reaches q.
double percentile(const std::vector<std::pair<double, double>>& dm, double total, double q) {
    double cum = 0;
    for (const auto& [d, w] : dm) {
        cum += w;
        if (cum >= q * total * (1 - 1e-12))
            return d;
    }
    return dm.empty() ? 0.0 : dm.back().first;
}

/// The grading of every piece (each fine by itself) of a frame; `acc` holds the fines (id -2)
/// of the frame left by pieces().
Grading grading(const model::Model& m, const std::vector<std::size_t>& bodies,
                const std::vector<Piece>& frags, const std::vector<Piece>& acc, double cutoff) {
    Grading g;
    std::vector<std::pair<double, double>> dm; // (diameter, mass)
    for (const auto& p : frags)
        if (p.id >= 0) {
            dm.emplace_back(diameter(p.volume, m.dimension), p.mass);
            g.fragments += 1;
        } else {
            g.fines_mass += p.mass;
        }
    for (const auto b : bodies)
        for (auto i = m.bodies.node_offsets[b]; i < m.bodies.node_offsets[b + 1]; ++i) {
            const Piece& p = acc[static_cast<std::size_t>(i)];
            if (p.nodes > 0 && p.id == -2) {
                dm.emplace_back(diameter(p.volume, m.dimension), p.mass);
                g.fines += 1;
            }
        }
    std::sort(dm.begin(), dm.end());
    for (const auto& [d, w] : dm) {
        g.mass += w;
        g.bp += w * std::max(0.0, std::log(d / cutoff));
    }
    g.bp = g.mass > 0 ? g.bp / g.mass : 0.0;
    g.d10 = percentile(dm, g.mass, 0.1);
    g.d50 = percentile(dm, g.mass, 0.5);
    g.d90 = percentile(dm, g.mass, 0.9);
    return g;
}

/// Largest fragment (fines excluded) over its parent's mass: mean and least over the grains.
void largest(const std::vector<Piece>& frags, std::size_t grains, Grading& g) {
    double sum = 0, least = 1, big = 0, parent = 0;
    for (std::size_t k = 0; k < frags.size(); ++k) {
        const Piece& p = frags[k];
        parent += p.mass;
        if (p.id >= 0)
            big = std::max(big, p.mass);
        if (k + 1 == frags.size() || frags[k + 1].body != p.body) {
            const double r = parent > 0 ? big / parent : 0.0;
            sum += r;
            least = std::min(least, r);
            big = parent = 0;
        }
    }
    g.largest_mean = grains ? sum / static_cast<double>(grains) : 0.0;
    g.largest_min = grains ? least : 0.0;
}

void put(const OutFile& out, const std::string& path, const std::string& line) {
    if (std::fputs(line.c_str(), out.get()) < 0)
        throw InputError(fmt::format("{}: write failed (disk full?)", path));
}

std::string fragment_row(std::int64_t step, double time, const Piece& p, int dim) {
    const double w = p.mass > 0 ? 1 / p.mass : 0.0;
    return fmt::format("{},{:.17g},{},{},{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},"
                       "{:.17g},{:.17g},{:.17g}\n",
                       step, time, p.id, p.body, p.nodes, p.volume, p.mass, diameter(p.volume, dim),
                       p.mx[0] * w, p.mx[1] * w, p.mx[2] * w, p.mv[0] * w, p.mv[1] * w,
                       p.mv[2] * w);
}

/// The default cut-off: the equivalent diameter of `fines_nodes` nodes of the mean volume.
double default_cutoff(const model::Model& m, const std::vector<std::size_t>& bodies,
                      std::int64_t fines_nodes) {
    double vol = 0, count = 0;
    for (const auto b : bodies)
        for (auto i = m.bodies.node_offsets[b]; i < m.bodies.node_offsets[b + 1]; ++i) {
            vol += m.nodes.volume[static_cast<std::size_t>(i)];
            count += 1;
        }
    return count > 0 ? diameter(static_cast<double>(fines_nodes) * vol / count, m.dimension) : 0.0;
}

constexpr const char* psd_header = "step,time,fragments,fines,fines_mass,mass,d10,d50,d90,"
                                   "largest_over_parent_mean,largest_over_parent_min,B_p,B_t,"
                                   "B_r\n";

std::string psd_row(std::int64_t step, double time, const Grading& g, double bp0) {
    const double bt = bp0 - g.bp;
    return fmt::format("{},{:.17g},{},{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},"
                       "{:.17g},{:.17g},{:.17g},{:.17g}\n",
                       step, time, g.fragments, g.fines, g.fines_mass, g.mass, g.d10, g.d50, g.d90,
                       g.largest_mean, g.largest_min, g.bp, bt, bp0 > 0 ? bt / bp0 : 0.0);
}

} // namespace

FragmentCounts write_fragments_csv(const h5::File& f, const model::Model& m,
                                   const FragmentOptions& opt, const std::string& fragments_csv,
                                   const std::string& psd_csv, const Progress& progress) {
    store::FrameReader frames(f);
    const auto n = m.nodes.volume.size();
    const auto fields = frames.fields();
    const auto has = [&](const char* name) {
        return std::find(fields.begin(), fields.end(), name) != fields.end();
    };
    if (!has("fragment") || frames.num_nodes() != n)
        throw SchemaError(f.name(), std::string(store::path::particles) + "/fragment",
                          "missing (fragments.csv needs the fragment frame field: add "
                          "\"fragment\" to the scene's solver.fields)");
    const bool has_v = has("velocity");
    const auto bodies = counted_bodies(f, m);
    FragmentCounts c;
    c.cutoff = opt.cutoff > 0 ? opt.cutoff : default_cutoff(m, bodies, opt.fines_nodes);
    auto frag_out = open_output(fragments_csv);
    auto psd_out = open_output(psd_csv);
    put(frag_out, fragments_csv,
        "step,time,fragment,body,nodes,volume,mass,diameter,x,y,z,vx,vy,vz\n");
    put(psd_out, psd_csv, psd_header);
    std::vector<Piece> acc(n);
    std::optional<double> bp0;
    for (std::size_t k = 0; k < frames.num_frames(); ++k) {
        const auto frag = frames.read("fragment", k);
        const auto x = frames.read("position", k);
        const auto v = has_v ? frames.read("velocity", k) : std::vector<double>{};
        if (frag.size() != n || x.size() != 3 * n || (has_v && v.size() != 3 * n))
            throw SchemaError(
                f.name(), store::path::particles,
                fmt::format("frame {} has a field of the wrong length (n = {})", k, n));
        const auto ps = pieces(m, bodies, frag, x, v, opt.fines_nodes, acc);
        for (const auto& p : ps)
            put(frag_out, fragments_csv,
                fragment_row(frames.step(k), frames.time(k), p, m.dimension));
        Grading g = grading(m, bodies, ps, acc, c.cutoff);
        largest(ps, bodies.size(), g);
        if (!bp0)
            bp0 = g.bp;
        put(psd_out, psd_csv, psd_row(frames.step(k), frames.time(k), g, *bp0));
        c.rows += ps.size();
        c.frames += 1;
        if (progress)
            progress("fragments", k + 1, frames.num_frames());
    }
    put(psd_out, psd_csv,
        fmt::format("# pd-post psd.csv from {}: {} counted bodies (moving particles, not fixed or "
                    "driven); a piece "
                    "of fewer than {} nodes is a fine; d = equivalent diameter (m; 2D of the "
                    "area, 3D of the volume); d10/d50/d90 = mass-weighted, smallest d whose "
                    "cumulative mass fraction reaches 0.1/0.5/0.9, over every piece fines "
                    "included; B_p = sum w ln(d/d_cut)+ (w mass fraction), d_cut = {:.6g} m; "
                    "B_t = B_p(first frame) - B_p; B_r = B_t / B_p(first frame) (Hardin 1985)\n",
                    f.name(), bodies.size(), opt.fines_nodes, c.cutoff));
    put(frag_out, fragments_csv,
        fmt::format("# pd-post fragments.csv from {}: fragment = smallest node index of the "
                    "connected component of intact bonds (/particles/nodes/fragment); -1 = the "
                    "fines of the body (pieces of fewer than {} nodes, summed); x, y, z = mass "
                    "centre (m), vx, vy, vz = mass-weighted velocity (m s-1); diameter = "
                    "equivalent diameter (m)\n",
                    f.name(), opt.fines_nodes));
    if (std::fflush(frag_out.get()) != 0 || std::fflush(psd_out.get()) != 0)
        throw InputError(fmt::format("{}: write failed (disk full?)", fragments_csv));
    return c;
}

} // namespace pd::post
