// SPDX-License-Identifier: MIT
#include "core/errors.hpp"
#include "pipeline/peridem/import.hpp"

#include <algorithm>
#include <set>

namespace pd::pipeline::peridem {

void read_output(Import& im) {
    const YAML::Node& R = im.R;
    const double final_time = im.final_time, dt = im.dt;
    const std::string& time_scheme = im.time_scheme;
    // ---- Output, solver
    json solver{{"final_time", final_time},
                {"dt", dt},
                {"integrator",
                 time_scheme == "central_difference" ? "symplectic_euler" : "velocity_verlet"},
                {"surface_correction", false},
                {"quadrature_calibration", false},
                // PeriDEM runs its deck's dt whatever the estimate says: a warning, not a refusal
                {"dt_above_estimate", "warn"},
                // nor stops where a node tunnels into a grain: a warning, and the run goes on
                {"penetration", "warn"}};
    if (auto out = R["Output"]) {
        const double every = num_or(out, "Output", "Output_Interval", 0);
        if (every > 0)
            solver["output_interval"] = std::min(every * dt, final_time);
        if (auto tags = child(out, "Tags"); tags && tags.IsSequence()) {
            json fields = json::array();
            std::set<std::string> have;
            for (const auto& t : tags) {
                const auto s = t.as<std::string>();
                std::string f = s == "Velocity"                    ? "velocity"
                                : s == "Displacement"              ? "displacement"
                                : s == "Force"                     ? "force"
                                : s == "Damage" || s == "Damage_Z" ? "damage"
                                                                   : "";
                if (!f.empty() && have.insert(f).second)
                    fields.push_back(f);
            }
            solver["fields"] = fields;
        }
    }
    im.solver = solver;
}

std::string scene_text(const Import& im, const std::string& yaml_path) {
    const YAML::Node& R = im.R;
    const Log& log = im.log;
    const int dim = im.dim, nz = im.nz;
    const bool plane_strain = im.plane_strain, lps_parity = im.lps_parity;
    const json &materials = im.materials, &discretization = im.discretization, &shapes = im.shapes,
               &contact = im.contact, &conditions = im.conditions, &solver = im.solver;
    const auto& zshape = im.zshape;
    const auto& parts = im.parts;
    // ---- The scene
    json scene;
    scene["title"] = fmt::format("imported from PeriDEM deck {}", fs::path(yaml_path).string());
    scene["dimension"] = dim;
    if (plane_strain || lps_parity)
        scene["planar"] = "plane_strain"; // parity: the equivalent material is given as K3', mu'
    scene["materials"] = materials;
    scene["discretization"] = discretization;
    scene["shapes"] = shapes;
    json plist = json::array();
    auto vec = [&](const std::array<double, 3>& v) {
        return dim == 3 ? json{v[0], v[1], v[2]} : json{v[0], v[1]};
    };
    for (const auto& p : parts) {
        const auto& zs = zshape[static_cast<std::size_t>(p.zone - 1)];
        json j{{"shape", fmt::format("zone_{}", p.zone)}, {"center", vec(p.x)}};
        if (p.scaled) {
            // PeriDEM scales by r / Parameters[0] (spec 2.5); pdgrain by radius / bounding radius.
            j["radius"] = p.r / zs.p0 * zs.shape.bounding_radius();
            if (p.o != 0)
                j["orientation"] = p.o;
        }
        j["material"] = fmt::format("zone_{}", p.zone);
        j["group"] = p.zone - 1;
        if (p.v != std::array<double, 3>{0, 0, 0})
            j["velocity"] = vec(p.v);
        if (p.fixed)
            j["fixed"] = true;
        if (std::any_of(im.zones.begin(), im.zones.end(),
                        [&](const Zone& z) { return z.k == p.zone && z.wall; }))
            j["wall"] = true; // PeriDEM's particle damping reaches grains through its nodes
        plist.push_back(j);
    }
    scene["particles"] = plist;
    if (!contact.empty())
        scene["contact"] = contact;
    json loading = json::object();
    if (auto g = child(R["Force_BC"], "Gravity")) {
        auto gv = nums(R["Force_BC"], "Force_BC", "Gravity");
        if (gv.size() < static_cast<std::size_t>(dim))
            throw ConfigError("Force_BC.Gravity", fmt::format("expected {} components", dim));
        loading["gravity"] = vec({gv[0], gv[1], dim == 3 ? gv[2] : 0.0});
    }
    if (!conditions.empty())
        loading["conditions"] = conditions;
    if (!loading.empty())
        scene["loading"] = loading;
    scene["solver"] = solver;
    log.info("{}: {} zones, {} particles ({} fixed), {} conditions", yaml_path, nz, parts.size(),
             std::count_if(parts.begin(), parts.end(), [](const Particle& p) { return p.fixed; }),
             conditions.size());
    return scene.dump(2) + "\n";
}

} // namespace pd::pipeline::peridem
