// SPDX-License-Identifier: MIT
#include "core/errors.hpp"
#include "mesh/discretize.hpp"
#include "pipeline/scene/build.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pd::pipeline::scene {

namespace {

/// Grains must not overlap: for every pair whose bounding spheres intersect, no node of one may
/// lie inside the other's shape (exact shape tests in the reference frame).
void check_overlaps(const model::Model& m, const std::vector<Instance>& inst,
                    const std::map<std::string, ShapeSpec>& shapes) {
    const auto& B = m.bodies;
    const std::size_t nb = B.num();
    std::vector<std::size_t> order(nb);
    for (std::size_t k = 0; k < nb; ++k)
        order[k] = k;
    auto lo = [&](std::size_t b) { return B.center[3 * b] - B.bounding_radius[b]; };
    std::sort(order.begin(), order.end(), [&](auto a, auto b) { return lo(a) < lo(b); });
    auto inside = [&](std::size_t a, std::size_t b) -> std::int64_t {
        // First node of body a strictly inside body b's shape, or -1.
        const auto& sh = shapes.at(inst[b].shape).shape;
        const double c = std::cos(B.orientation[b]), sn = std::sin(B.orientation[b]);
        const double tol = 1e-9 * sh.bounding_radius();
        for (auto i = B.begin(a); i < B.end(a); ++i) {
            const double* x = &m.nodes.x0[3 * static_cast<std::size_t>(i)];
            const double dx = x[0] - B.center[3 * b], dy = x[1] - B.center[3 * b + 1],
                         dz = x[2] - B.center[3 * b + 2];
            const double s = B.scale[b];
            const double X = (c * dx + sn * dy) / s, Y = (-sn * dx + c * dy) / s, Z = dz / s;
            if (sh.clearance(X, Y, Z) > tol)
                return i - B.begin(a);
        }
        return -1;
    };
    for (std::size_t ia = 0; ia < nb; ++ia) {
        const auto a = order[ia];
        for (std::size_t ib = ia + 1; ib < nb; ++ib) {
            const auto b = order[ib];
            if (lo(b) > B.center[3 * a] + B.bounding_radius[a])
                break;
            const double d = std::hypot(B.center[3 * a] - B.center[3 * b],
                                        B.center[3 * a + 1] - B.center[3 * b + 1],
                                        B.center[3 * a + 2] - B.center[3 * b + 2]);
            if (d >= B.bounding_radius[a] + B.bounding_radius[b])
                continue;
            std::size_t p = a, q = b;
            auto node = inside(a, b);
            if (node < 0) {
                node = inside(b, a);
                std::swap(p, q);
            }
            if (node >= 0)
                throw ConfigError(
                    fmt::format("{}, {}", inst[std::min(p, q)].where, inst[std::max(p, q)].where),
                    fmt::format("grains overlap: node {} of the {} lies inside the {}", node,
                                p < q ? "first" : "second", p < q ? "second" : "first"));
        }
    }
}

/// Places the instances and sets each grain's mesh size and horizon (spec 2.3, 2.5).
void place_grains(SceneBuild& s) {
    model::Model& m = s.m;
    const Log& log = s.log;
    const auto& inst = s.inst;
    const auto& refs = s.refs;
    const auto& shapes = s.shapes;
    auto& h_nominal_of = s.h_nominal_of;
    const auto& [small_horizon_warns, partial_cutoff, h_ref, has_h, has_m, has_r, horizon_key,
                 horizon_abs, horizon_factor] = s.dz;
    std::size_t small_horizons = 0;
    double small_ratio = std::numeric_limits<double>::infinity();
    // Place instances: x = t + s R(theta) X, volumes x s^d, h x s (spec 2.5).
    auto& B = m.bodies;
    for (std::size_t k = 0; k < inst.size(); ++k) {
        const auto& d = inst[k];
        const auto& r = refs.at(d.shape);
        const auto& ref = m.ref_meshes[static_cast<std::size_t>(r.index)];
        const double s = d.radius > 0 ? d.radius / shapes.at(d.shape).shape.bounding_radius() : 1.0;
        const std::size_t nref = ref.nodes.size() / 3;
        mesh::place_instance(ref, d.orientation, s, d.center, m.nodes.x0);
        const double sd = std::pow(s, m.dimension);
        for (std::size_t i = 0; i < nref; ++i) {
            m.nodes.volume.push_back(r.volume[i] * sd);
            m.nodes.body.push_back(static_cast<std::int32_t>(k));
        }
        B.node_offsets.push_back(B.node_offsets.back() + static_cast<model::offset_t>(nref));
        B.material.push_back(d.material);
        B.group.push_back(d.group);
        B.ref_mesh.push_back(r.index);
        B.kind.push_back(d.wall ? model::BodyKind::wall : model::BodyKind::particle);
        B.fixed.push_back(d.fixed ? 1 : 0);
        B.center.insert(B.center.end(), d.center.begin(), d.center.end());
        B.bounding_radius.push_back(r.bound * s);
        B.orientation.push_back(d.orientation);
        B.scale.push_back(s);
        B.initial_velocity.insert(B.initial_velocity.end(), d.velocity.begin(), d.velocity.end());
        const double h = r.h * s;
        const auto& spec = shapes.at(d.shape);
        const double h_nominal = spec.mesh_size > 0 ? spec.mesh_size : h_ref;
        const double delta = has_h   ? horizon_abs
                             : has_m ? horizon_factor * h_nominal
                                     : horizon_factor * h;
        if (delta < 2.0 * h && small_horizon_warns) {
            ++small_horizons;
            small_ratio = std::min(small_ratio, delta / h);
        } else if (delta < 2.0 * h)
            throw ConfigError(horizon_key,
                              fmt::format("{}: horizon {:.4g} m is less than 2 x its mesh "
                                          "spacing h = {:.4g} m (too coarse: refine mesh_size "
                                          "or enlarge the horizon)",
                                          d.where, delta, h));
        B.mesh_size.push_back(h);
        B.horizon.push_back(delta);
        h_nominal_of.push_back(h_nominal);
    }
    if (small_horizons > 0)
        log.warn("{}: {} grain(s) have a horizon below 2 x their smallest node spacing (down to "
                 "{:.3g} h): few bonds per node, a stiffer and more mesh-dependent response "
                 "(discretization.small_horizon = \"warn\")",
                 horizon_key, small_horizons, small_ratio);
}

/// Logs the sum of nodal volumes against the exact shapes'.
void report_volumes(const model::Model& m, const std::vector<Instance>& inst,
                    const std::map<std::string, ShapeSpec>& shapes, const Log& log) {
    const auto& B = m.bodies;
    double vol = 0, exact = 0;
    for (double v : m.nodes.volume)
        vol += v;
    for (std::size_t b = 0; b < B.num(); ++b)
        exact +=
            shapes.at(inst[b].shape).shape.area_or_volume() * std::pow(B.scale[b], m.dimension);
    log.info("{} particles: sum of nodal volumes {:.6e} m{} against {:.6e} m{} of the exact "
             "shapes ({:+.3f}%)",
             B.num(), vol, m.dimension, exact, m.dimension, 100.0 * (vol - exact) / exact);
}

} // namespace

void place_particles(SceneBuild& s) {
    model::Model& m = s.m;
    place_grains(s);
    check_overlaps(m, s.inst, s.shapes);
    report_volumes(m, s.inst, s.shapes, s.log);
    m.bonds = model::build_bonds(m.nodes, m.bodies, s.dz.partial_cutoff);
}

void mark_surface_layer(SceneBuild& s) {
    model::Model& m = s.m;
    const auto& B = m.bodies;
    const auto& inst = s.inst;
    const auto& refs = s.refs;
    // Surface-layer nodes: within R_c + h/2 + min(R_c, h) of their grain's boundary (R_c the
    // largest contact radius; 2 R_c + h/2 when R_c <= h). A node of another grain within
    // min(R_c, h) of a node below the layer is more than R_c + h/2 inside: pd-solve's
    // interpenetration guard (solver/contact.hpp Penetration). The layer is no thicker than
    // R_c + 1.5 h, so grains of a few R_c (R_c = 3 mesh_size) still have nodes below it.
    // Also the partitioner's weight. The contact search takes every node of grains near each
    // other, whatever its depth.
    {
        double rc_max = 0;
        for (const auto& p : m.contact)
            rc_max = std::max(rc_max, p.radius);
        m.nodes.surface.resize(m.nodes.num());
        for (std::size_t b = 0; b < B.num(); ++b) {
            const auto& bd = refs.at(inst[b].shape).bdist;
            for (auto i = B.begin(b); i < B.end(b); ++i) {
                const auto k = static_cast<std::size_t>(i - B.begin(b));
                const double h = B.mesh_size[b];
                m.nodes.surface[static_cast<std::size_t>(i)] =
                    bd[k] * B.scale[b] <= rc_max + 0.5 * h + std::min(rc_max, h) ? 1 : 0;
            }
        }
    }
}

} // namespace pd::pipeline::scene
