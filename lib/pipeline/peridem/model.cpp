// SPDX-License-Identifier: MIT
#include "core/errors.hpp"
#include "pipeline/peridem/import.hpp"

#include <algorithm>
#include <cstdlib>

namespace pd::pipeline::peridem {

void read_model(Import& im) {
    const YAML::Node& R = im.R;
    const Log& log = im.log;
    // ---- Model
    const YAML::Node model = R["Model"];
    if (!model)
        throw ConfigError("Model", "missing (required)");
    const int dim = int_or(model, "Model", "Dimension", 0, 0, 3);
    if (dim != 2 && dim != 3)
        throw ConfigError("Model.Dimension", "expected 2 or 3 (required)");
    const double final_time = num_or(model, "Model", "Final_Time", 0);
    const double steps = num_or(model, "Model", "Time_Steps", 0);
    if (!(final_time > 0))
        throw ConfigError("Model.Final_Time", "must be > 0 (required)");
    if (!(steps >= 1))
        throw ConfigError("Model.Time_Steps", "must be >= 1 (required)");
    const double dt = final_time / steps;
    const YAML::Node disc = child(model, "Discretization_Type");
    const auto time_scheme =
        str_or(disc, "Model.Discretization_Type", "Time", "central_difference");
    if (time_scheme != "central_difference" && time_scheme != "velocity_verlet")
        throw ConfigError("Model.Discretization_Type.Time",
                          "'" + time_scheme + "': expected central_difference or velocity_verlet");
    const auto spatial = str_or(disc, "Model.Discretization_Type", "Spatial", "finite_difference");
    if (spatial != "finite_difference")
        throw ConfigError("Model.Discretization_Type.Spatial",
                          "'" + spatial + "': only finite_difference is imported");
    const bool single =
        str_or(model, "Model", "Particle_Sim_Type",
               R["Particle"] ? "Multi_Particle" : "Single_Particle") == "Single_Particle";
    const auto seed = static_cast<std::uint32_t>(num_or(model, "Model", "Seed", 1));
    if (steps < 10)
        log.warn("Model.Time_Steps = {} gives dt = {:.4g} s: far above any stable step; set "
                 "solver.dt before solving (pd-solve refuses it)",
                 steps, dt);
    im.dim = dim;
    im.final_time = final_time;
    im.dt = dt;
    im.time_scheme = time_scheme;
    im.single = single;
    im.seed = seed;
}

void read_zones(Import& im) {
    const YAML::Node& R = im.R;
    const Log& log = im.log;
    const bool single = im.single;
    auto& zones = im.zones;
    // ---- Zones
    const bool old_format = static_cast<bool>(R["Wall"]);
    int nz = int_or(R["Zone"], "Zone", "Zones", 0, 0, 100000);
    if (nz <= 0) {
        const YAML::Node mat = R["Material"];
        if (mat && mat.IsMap())
            for (auto it = mat.begin(); it != mat.end(); ++it)
                nz = std::max(nz, std::atoi(it->first.as<std::string>().c_str() + 5));
    }
    if (nz <= 0)
        throw ConfigError("Zone.Zones", "missing: the number of zones");
    if (single && nz != 1)
        throw ConfigError("Zone.Zones", "a Single_Particle deck has one zone");
    zones.resize(static_cast<std::size_t>(nz));
    for (int k = 1; k <= nz; ++k) {
        auto& z = zones[static_cast<std::size_t>(k - 1)];
        z.k = k;
        const std::string zk = fmt::format("Zone_{}", k);
        const YAML::Node zn = child(R["Zone"], zk);
        z.wall = flag_or(zn, "Zone." + zk, "Is_Wall", false);
        const YAML::Node pz = child(R["Particle"], zk);
        const YAML::Node wz = child(R["Wall"], zk);
        if (z.wall && old_format) {
            // Pre-2024 format: the wall's geometry is in Zone, its mesh used as is (spec 8.3).
            z.from_geom = true;
            z.constrained = true;
            z.type = str_or(zn, "Zone." + zk, "Type", "");
            z.params = nums(zn, "Zone." + zk, "Parameters");
            if (wz && !flag_or(wz, "Wall." + zk, "All_Dofs_Constrained", true))
                log.info("Wall.{}.All_Dofs_Constrained = false: pre-2024 walls are never "
                         "integrated, imported as constrained (moved only by its displacement "
                         "conditions)",
                         zk);
        } else {
            const std::string w = "Particle." + zk;
            z.type = str_or(pz, w, "Type", "");
            z.params = nums(pz, w, "Parameters");
            z.constrained = flag_or(pz, w, "All_Dofs_Constrained", false);
            z.from_geom =
                single || flag_or(pz, w, "Create_Particle_Using_ParticleZone_GeomObject", false);
            const YAML::Node rp = child(child(R["Mesh"], zk), "Reference_Particle");
            if (rp) {
                z.type = str_or(rp, "Mesh." + zk + ".Reference_Particle", "Type", z.type);
                auto p = nums(rp, "Mesh." + zk + ".Reference_Particle", "Parameters");
                if (!p.empty())
                    z.params = p;
            }
        }
    }
    im.old_format = old_format;
    im.nz = nz;
}

} // namespace pd::pipeline::peridem
