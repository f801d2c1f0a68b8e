// SPDX-License-Identifier: MIT
#include "core/errors.hpp"
#include "pipeline/scene/build.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>

namespace pd::pipeline::scene {

namespace {

const std::vector<std::string> law_keys = {
    "radius_factor", "radius", "radius_mesh_factor", "stiffness", "stiffness_factor", "restitution",
    "friction",      "law",    "approach_damping"};

/// The default surface law's stiffness c = surface_beta kappa / h^2 (N m-5), kappa the pair's
/// harmonic bulk modulus, h the coarser nominal mesh size of the two groups. A node of density
/// rho pressed into a surface then oscillates at omega^2 = c / rho ~ surface_beta kappa /
/// (rho h^2), of the order of the bonds' own highest mode (~ 2 E / (rho h^2) at delta = 3 h),
/// so the step stays of the bonds' order (measured: README "Contact"); the penalty's compliance,
/// a layer ~ h / surface_beta thick, vanishes with h (first order).
constexpr double surface_beta = 1.0;

/// The law of a scene that names none: the surface law (issue 26), whose stiffness comes from
/// the materials and the mesh with no factor. PeriDEM's node-to-node law stays for scenes that
/// name it ("law": "node") or give it a radius or a numeric stiffness (PeriDEM decks).
constexpr model::ContactLaw default_law = model::ContactLaw::surface;

const auto with = [](std::vector<std::string> v, std::initializer_list<std::string> more) {
    v.insert(v.end(), more);
    return v;
};

/// Prints each group's horizon and smallest node spacing (min-max over its grains) and each
/// contact law's stiffness and radius; warns when the horizons of groups that can touch (a law
/// with Kn > 0 between them, or a group with itself) differ by more than 20 %: the contact
/// stiffness (~ delta^-(d+2)) and the bond response then differ between them.
void report_horizons(const model::Model& m, const Log& log) {
    const auto& B = m.bodies;
    struct Range {
        std::size_t n = 0;
        double dmin = 1e300, dmax = 0, hmin = 1e300, hmax = 0;
    };
    std::map<std::int32_t, Range> by_group;
    for (std::size_t b = 0; b < B.num(); ++b) {
        auto& r = by_group[B.group[b]];
        ++r.n;
        r.dmin = std::min(r.dmin, B.horizon[b]);
        r.dmax = std::max(r.dmax, B.horizon[b]);
        r.hmin = std::min(r.hmin, B.mesh_size[b]);
        r.hmax = std::max(r.hmax, B.mesh_size[b]);
    }
    for (const auto& [g, r] : by_group)
        log.info("group {}: {} grains, horizon {:.4g}-{:.4g} m, smallest node spacing "
                 "{:.4g}-{:.4g} m",
                 g, r.n, r.dmin, r.dmax, r.hmin, r.hmax);
    for (const auto& p : m.contact) {
        const auto a = by_group.find(p.group_a), b = by_group.find(p.group_b);
        if (p.law == model::ContactLaw::surface)
            log.info("contact groups {}-{}: surface law, c {:.4g} N m-5, reach h {:.4g} m",
                     p.group_a, p.group_b, p.stiffness, p.radius);
        else
            log.info("contact groups {}-{}: stiffness Kn {:.4g}, radius R_c {:.4g} m", p.group_a,
                     p.group_b, p.stiffness, p.radius);
        if (!(p.stiffness > 0) || a == by_group.end() || b == by_group.end())
            continue; // no contact, or a rigid wall (no horizon)
        const double lo = std::min(a->second.dmin, b->second.dmin);
        const double hi = std::max(a->second.dmax, b->second.dmax);
        if (hi > 1.2 * lo)
            log.warn(
                "contact groups {}-{}: horizons range over {:.4g}-{:.4g} m ({:+.0f} %): "
                "grains that touch have different contact stiffness (~ delta^-{}) and bond "
                "response (use horizon, or horizon_factor with one mesh_size for their shapes)",
                p.group_a, p.group_b, lo, hi, 100.0 * (hi - lo) / lo, m.dimension + 2);
    }
}

/// The contact laws of pairs of groups: the default law in "contact", overridden by "pairs".
struct ContactLaws {
    const json& c;
    const model::Model& m;
    const std::vector<double>& h_nominal_of;
    double h_ref, hmin, delta_max;

    double group_modulus(std::int32_t g) const {
        const auto& B = m.bodies;
        double k = 0;
        for (std::size_t b = 0; b < B.num(); ++b)
            if (B.group[b] == g)
                k = std::max(k,
                             m.materials[static_cast<std::size_t>(B.material[b])].bulk_modulus());
        return k; // 0 for a group of rigid walls only
    }

    /// The nominal mesh size of the pair (the coarser of the two groups'; a rigid wall's group
    /// takes the grains').
    double pair_mesh_size(std::int32_t ga, std::int32_t gb) const {
        double h_pair = 0;
        for (std::size_t b = 0; b < m.bodies.num(); ++b)
            if (m.bodies.group[b] == ga || m.bodies.group[b] == gb)
                h_pair = std::max(h_pair, h_nominal_of[b]);
        return h_pair > 0 ? h_pair : h_ref;
    }

    double pair_modulus(std::int32_t ga, std::int32_t gb) const {
        double ka = group_modulus(ga), kb = group_modulus(gb);
        if (ka == 0)
            ka = kb;
        if (kb == 0)
            kb = ka;
        return ka > 0 ? 2 * ka * kb / (ka + kb) : 0;
    }

    /// restitution and friction of any law: given, else (fresh) the defaults, else inherited.
    static void restitution_friction(const json& o, const std::string& w, model::ContactPair& p,
                                     bool fresh) {
        if (o.contains("restitution") || fresh) {
            p.restitution = number(o, w, "restitution", fresh ? 1.0 : p.restitution);
            if (!(p.restitution > 0 && p.restitution <= 1))
                throw ConfigError(w + ".restitution", "must be in (0, 1]");
        }
        if (o.contains("friction") || fresh) {
            p.friction = number(o, w, "friction", fresh ? 0.0 : p.friction);
            if (p.friction < 0)
                throw ConfigError(w + ".friction", "must be >= 0");
        }
    }

    /// The node-to-surface law: c = surface_beta kappa / h^2 x stiffness_factor, or a given
    /// stiffness (N m-5); restitution and friction as for any law. `automatic`: whether c is
    /// the rule's (computed here, or kept from a base whose c was), which
    /// raise_for_speed (contact_speed.cpp) may raise once the scene's speeds are known.
    model::ContactPair surface_law(const json& o, const std::string& w, model::ContactPair p,
                                   bool inherit, bool keep_stiffness, bool& automatic) const {
        for (const char* k : {"radius", "radius_factor", "radius_mesh_factor"})
            if (o.contains(k))
                throw ConfigError(w + "." + k, "the surface law has no contact radius (it acts "
                                               "from contact on); give law \"node\" for one");
        p.radius = pair_mesh_size(p.group_a, p.group_b);
        if (o.contains("approach_damping"))
            throw ConfigError(w + ".approach_damping",
                              "PeriDEM's particle damping belongs to the node law (law \"node\")");
        p.approach = 0;
        restitution_friction(o, w, p, !inherit);
        if (o.contains("stiffness") && !o["stiffness"].is_string()) {
            p.stiffness = number(o, w, "stiffness", 0); // N m-5; 0: this pair does not interact
            if (p.stiffness < 0)
                throw ConfigError(w + ".stiffness", "must be >= 0 (0 = no contact), or \"auto\"");
            automatic = false;
        } else if (o.contains("stiffness") || o.contains("stiffness_factor") || !keep_stiffness) {
            text(o, w, "stiffness", "auto", {"auto"});
            p.stiffness = surface_beta * pair_modulus(p.group_a, p.group_b) /
                          (p.radius * p.radius) * number(o, w, "stiffness_factor", 1.0);
            automatic = true;
        }
        return p;
    }

    /// The law: as given; else node-to-node when a radius or a numeric stiffness (N m-7, a node
    /// law's unit) is given (PeriDEM decks, older scenes); else the base's; else default_law.
    static model::ContactLaw choose_law(const json& o, const std::string& w,
                                        const model::ContactPair* base) {
        if (o.contains("law"))
            return text(o, w, "law", "surface", {"surface", "node"}) == "node"
                       ? model::ContactLaw::node
                       : model::ContactLaw::surface;
        if (o.contains("radius") || o.contains("radius_factor") ||
            o.contains("radius_mesh_factor") ||
            (o.contains("stiffness") && !o["stiffness"].is_string()))
            return model::ContactLaw::node;
        return base ? base->law : default_law;
    }

    /// `automatic`: in, whether the base's stiffness is the surface law's rule; out, this law's.
    model::ContactPair make_law(const json& o, const std::string& w, std::int32_t ga,
                                std::int32_t gb, const model::ContactPair* base,
                                bool& automatic) const {
        const auto& B = m.bodies;
        model::ContactPair p = base ? *base : model::ContactPair{};
        p.group_a = ga;
        p.group_b = gb;
        p.law = choose_law(o, w, base);
        const bool law_changed = base && p.law != base->law;
        if (p.law == model::ContactLaw::surface)
            return surface_law(o, w, p, base != nullptr, base && !law_changed, automatic);
        automatic = false;

        const int radius_keys = int(o.contains("radius")) + int(o.contains("radius_factor")) +
                                int(o.contains("radius_mesh_factor"));
        if (radius_keys > 1)
            throw ConfigError(w, "give at most one of radius (m), radius_factor (multiple of the "
                                 "smallest node spacing) or radius_mesh_factor (multiple of "
                                 "mesh_size)");
        // The node spacing of the stiffness rule below: the smallest node spacing of the scene
        // (PeriDEM), or with radius_mesh_factor (here or inherited from the default law) the
        // pair's nominal mesh size, so that Kn R_c^(d+1) keeps the contact layer's pressure per
        // overlap tied to the same h as R_c.
        const bool mesh_radius = o.contains("radius_mesh_factor") ||
                                 (base && c.contains("radius_mesh_factor") &&
                                  !o.contains("radius") && !o.contains("radius_factor"));
        double h_pair = 0;
        for (std::size_t b = 0; b < B.num(); ++b)
            if (B.group[b] == ga || B.group[b] == gb)
                h_pair = std::max(h_pair, h_nominal_of[b]);
        if (!(h_pair > 0))
            h_pair = h_ref;
        const double h_law = mesh_radius ? h_pair : hmin;
        if (o.contains("radius"))
            p.radius = positive(o, w, "radius", 0);
        else if (o.contains("radius_mesh_factor")) {
            // R_c = factor x the coarser nominal mesh size of the two groups (the shapes'
            // mesh_size, else the scene's; a rigid wall's group takes the grains'): at R_c >= 3
            // h a node always has several partner nodes in reach, so it cannot slip through the
            // gap between two nodes of the other grain (R_c = 0.95 h_min lets a sharp tip or a
            // hard press push a node through; README "Contact"), and R_c -> 0 with h.
            p.radius = positive(o, w, "radius_mesh_factor", 0) * h_pair;
        } else if (o.contains("radius_factor") || !base)
            p.radius = positive(o, w, "radius_factor", 0.95) * hmin;
        restitution_friction(o, w, p, !base);
        if (o.contains("approach_damping") || !base) {
            p.approach = number(o, w, "approach_damping", 0.0);
            if (!(p.approach >= 0 && p.approach < 1e30))
                throw ConfigError(w + ".approach_damping", "must be in [0, 1e30)");
            if (p.approach > 0 && m.dimension != 2)
                throw ConfigError(w + ".approach_damping",
                                  "PeriDEM's particle damping is 2D only (its grains weigh "
                                  "rho pi R^2)");
        }
        if (o.contains("stiffness") && !o["stiffness"].is_string()) {
            p.stiffness = number(o, w, "stiffness", 0); // 0: this pair does not interact
            if (p.stiffness < 0)
                throw ConfigError(w + ".stiffness", "must be >= 0 (0 = no contact), or \"auto\"");
        } else if (o.contains("stiffness") || o.contains("stiffness_factor") || !base) {
            text(o, w, "stiffness", "auto", {"auto"});
            // Kn = 18 kappa / (pi delta^(d+2)) (0.95 h_min / R_c)^(d+1): kappa the harmonic
            // mean of the two groups' bulk moduli (a rigid wall counts as the grain's own
            // modulus), delta the largest horizon. Dimensionally consistent in 2D and 3D (spec
            // decision 7). The last factor (1 at PeriDEM's R_c = 0.95 h) keeps the contact
            // layer's pressure per overlap, Kn times the integral of (R_c - r) over the partner's
            // nodes within R_c ~ Kn R_c^(d+1), when R_c grows: with R_c = 3 h the node-scale
            // roughness is gone and restitution and head-on impacts converge (measured in
            // tests/unit/solver/test_restitution.cpp).
            double ka = group_modulus(ga), kb = group_modulus(gb);
            if (ka == 0)
                ka = kb;
            if (kb == 0)
                kb = ka;
            const double kappa = ka > 0 ? 2 * ka * kb / (ka + kb) : 0;
            p.stiffness = 18.0 * kappa / (std::numbers::pi * std::pow(delta_max, m.dimension + 2)) *
                          std::pow(0.95 * h_law / p.radius, m.dimension + 1) *
                          number(o, w, "stiffness_factor", 1.0);
        }
        return p;
    }
};

} // namespace

void parse_contact(SceneBuild& s) {
    const json& root = s.root;
    model::Model& m = s.m;
    const auto& B = m.bodies;
    // Contact table: a default law for every pair of groups (particles and walls), overridden
    // per pair of groups under "pairs".
    const json empty = json::object();
    const json& c = root.contains("contact") ? root["contact"] : empty;
    check_keys(c, "contact", with(law_keys, {"pairs"}));
    double hmin = *std::min_element(B.mesh_size.begin(), B.mesh_size.end());
    std::set<std::int32_t> groups(B.group.begin(), B.group.end());
    for (const auto& wall : m.walls)
        groups.insert(wall.group);
    double delta_max = *std::max_element(B.horizon.begin(), B.horizon.end());
    const ContactLaws laws{c, m, s.h_nominal_of, s.dz.h_ref, hmin, delta_max};
    s.contact_auto.clear();
    for (auto ga : groups)
        for (auto gb : groups)
            if (gb >= ga) {
                bool automatic = false;
                m.contact.push_back(laws.make_law(c, "contact", ga, gb, nullptr, automatic));
                s.contact_auto.push_back(automatic ? 1 : 0);
            }
    if (c.contains("pairs")) {
        if (!c["pairs"].is_array())
            throw ConfigError("contact.pairs", "expected a list");
        for (std::size_t k = 0; k < c["pairs"].size(); ++k) {
            const json& pj = c["pairs"][k];
            const std::string w = fmt::format("contact.pairs[{}]", k);
            check_keys(pj, w, with(law_keys, {"groups"}));
            if (!pj.contains("groups") || !pj["groups"].is_array() || pj["groups"].size() != 2)
                throw ConfigError(w + ".groups", "expected two group numbers");
            const auto ga = static_cast<std::int32_t>(
                           std::clamp(pj["groups"][0].get<double>(), -1e9, 1e9)),
                       gb = static_cast<std::int32_t>(
                           std::clamp(pj["groups"][1].get<double>(), -1e9, 1e9));
            bool found = false;
            for (std::size_t q = 0; q < m.contact.size(); ++q) {
                auto& p = m.contact[q];
                if ((p.group_a == ga && p.group_b == gb) || (p.group_a == gb && p.group_b == ga)) {
                    bool automatic = s.contact_auto[q] != 0;
                    p = laws.make_law(pj, w, p.group_a, p.group_b, &p, automatic);
                    s.contact_auto[q] = automatic ? 1 : 0;
                    found = true;
                }
            }
            if (!found)
                throw ConfigError(w + ".groups",
                                  fmt::format("no particle or wall is in group {} or {}", ga, gb));
        }
    }

    report_horizons(m, s.log);
}

} // namespace pd::pipeline::scene
