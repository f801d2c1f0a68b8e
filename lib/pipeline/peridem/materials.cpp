// SPDX-License-Identifier: MIT
#include "core/errors.hpp"
#include "pipeline/peridem/import.hpp"

#include <cmath>

namespace pd::pipeline::peridem {

namespace {

/// The law of a Material block's Type.
std::string law_of(const YAML::Node& mn, const std::string& w) {
    const auto type = str_or(mn, w, "Type", "");
    std::string law;
    if (type == "PDState")
        law = "lps";
    else if (type == "PMBBond")
        law = "pmb";
    else if (type == "RNPBond")
        law = "rnp";
    else
        throw ConfigError(w + ".Type", type.empty()
                                           ? "missing (required): PDState, PMBBond or RNPBond"
                                           : "'" + type +
                                                 "' cannot be imported (PDState, "
                                                 "PMBBond or RNPBond)");
    return law;
}

struct Elastic {
    double E, K, G, nu;
    bool has_nu;
};

/// E and nu from any two of E, K, G (Mu), Lambda, Poisson_Ratio.
Elastic elastic_constants(const YAML::Node& mn, const std::string& w, const std::string& law,
                          const Log& log) {
    double E = num_or(mn, w, "E", 0), K = num_or(mn, w, "K", 0), G = num_or(mn, w, "G", 0),
           nu = num_or(mn, w, "Poisson_Ratio", std::nan(""));
    if (G == 0)
        G = num_or(mn, w, "Mu", 0);
    const double lambda = num_or(mn, w, "Lambda", 0);
    const bool has_nu = !std::isnan(nu);
    if (E > 0 && has_nu) {
    } else if (K > 0 && G > 0) {
        E = 9 * K * G / (3 * K + G);
        nu = (3 * K - 2 * G) / (2 * (3 * K + G));
    } else if (E > 0 && G > 0) {
        nu = E / (2 * G) - 1;
    } else if (K > 0 && has_nu) {
        E = 3 * K * (1 - 2 * nu);
    } else if (E > 0 && K > 0) {
        nu = (3 * K - E) / (6 * K);
    } else if (G > 0 && has_nu) {
        E = 2 * G * (1 + nu);
    } else if (lambda > 0 && G > 0) {
        E = G * (3 * lambda + 2 * G) / (lambda + G);
        nu = lambda / (2 * (lambda + G));
    } else if (law != "lps" && (E > 0 || K > 0)) {
        nu = 0.25;
        if (!(E > 0))
            E = 3 * K * (1 - 2 * nu);
        log.warn("{}: one elastic constant only, taking nu = 0.25", w);
    } else
        throw ConfigError(w, "give two of E, K, G, Poisson_Ratio (K and G in the examples)");
    if (!(E > 0))
        throw ConfigError(w, fmt::format("the elastic constants give E = {:.4g} Pa (must be "
                                         "positive)",
                                         E));
    return {E, K, G, nu, has_nu};
}

/// One zone's Material block -> a scene material.
struct MaterialReader {
    Import& im;
    bool lps_noted = false;
    bool compression_noted = false;
    double horizon = 0, ratio = 0; ///< of the last zone read

    void read(int k, std::vector<YAML::Node>& mat_nodes, bool plane_strain_deck) {
        const YAML::Node& R = im.R;
        const Log& log = im.log;
        const int dim = im.dim;
        const std::string w = fmt::format("Material.Zone_{}", k);
        YAML::Node mn = child(R["Material"], fmt::format("Zone_{}", k));
        if (!mn)
            throw ConfigError(w, "missing: every zone needs a material");
        if (auto c = child(mn, "Copy_Material_Data")) {
            const int from = int_of(c, w + ".Copy_Material_Data", 1, k - 1);
            if (from < 1 || from >= k)
                throw ConfigError(w + ".Copy_Material_Data",
                                  fmt::format("{} is not an earlier zone", from));
            mn.reset(mat_nodes[static_cast<std::size_t>(from - 1)]);
        }
        mat_nodes[static_cast<std::size_t>(k - 1)].reset(mn);
        const std::string law = law_of(mn, w);
        const double rho = num_or(mn, w, "Density", 0);
        if (!(rho > 0))
            throw ConfigError(w + ".Density", "missing or not positive (required)");
        const auto [E, K, G, nu, has_nu] = elastic_constants(mn, w, law, log);
        im.zone_bulk.resize(static_cast<std::size_t>(im.nz), 0.0);
        im.zone_bulk[static_cast<std::size_t>(k - 1)] = K > 0 ? K : E / (3 * (1 - 2 * nu));
        if (auto g = child(mn, "Gc"); g && !(num(g, w + ".Gc") > 0))
            throw ConfigError(w + ".Gc", "must be > 0 (J/m2); leave it out for an unbreakable "
                                         "material");
        double Gc = num_or(mn, w, "Gc", -1);
        if (Gc < 0 && child(mn, "KIc")) {
            const double kic = num_or(mn, w, "KIc", 0);
            Gc = kic * kic / E; // spec 1.2: plane-stress form, no nu
        }
        json m{{"law", law}, {"density", rho}, {"youngs_modulus", E}};
        if (law == "lps" && dim == 2) {
            lps_2d(w, E, nu, plane_strain_deck, m, Gc);
        } else if (law == "lps")
            m["poisson_ratio"] = nu;
        else if (has_nu || (K > 0 && G > 0))
            log.info("{}: law {} fixes its Poisson ratio; the deck's nu = {:.4g} is not used", w,
                     law, nu);
        if (Gc > 0) {
            m["fracture_energy"] = Gc;
            breaking(w, m);
        } else
            log.warn("{}: no Gc or KIc: the material is unbreakable", w);
        influence(mn, w, law, m);
        im.plane_strain = im.plane_strain || flag_or(mn, w, "Is_Plane_Strain", false);
        horizon = num_or(mn, w, "Horizon", 0);
        ratio = num_or(mn, w, "Horizon_Mesh_Ratio", 0);
        im.materials[fmt::format("zone_{}", k)] = m;
    }

    /// PeriDEM breaks bonds in compression too (|s| > s0, spec 1.3); pdgrain in tension only
    /// unless the material sets break_in_compression, which --parity peridem does.
    void breaking(const std::string& w, json& m) {
        if (im.parity) {
            m["break_in_compression"] = true;
            if (!compression_noted)
                im.log.info("{}: --parity peridem: bonds also break in compression (|s| > s0, "
                            "as PeriDEM; break_in_compression)",
                            w);
        } else if (!compression_noted)
            im.log.info("{}: bonds break in tension only (pdgrain's default); PeriDEM also "
                        "breaks them in compression (|s| > s0): --parity peridem sets "
                        "break_in_compression",
                        w);
        compression_noted = true;
    }

    /// PDState in 2D: pdgrain's consistent 2D LPS, or with --parity peridem the equivalent of
    /// PeriDEM 0.2's 2D PDState.
    void lps_2d(const std::string& w, double E, double nu, bool plane_strain_deck, json& m,
                double& Gc) {
        const Log& log = im.log;
        const bool parity = im.parity;
        bool& lps_parity = im.lps_parity;
        // PeriDEM 0.2's 2D PDState uses the 3D LPS formulas (theta = 3/m sum, 3K/m, 15G/m,
        // the 3D critical stretch); pdgrain's 2D LPS is the consistent one (theta = 2/m
        // sum, 2 kappa/m, 8 mu/m, the 2D s0). The two agree for mu' = 15 G / 8 and
        // kappa' = 9 K / 4 (the 2D bulk modulus; plane strain: K3' = kappa' - mu' / 3) and
        // a Gc' that keeps PeriDEM's s0.
        const double G3 = E / (2 * (1 + nu)), K3 = E / (3 * (1 - 2 * nu));
        const double mu_p = 15 * G3 / 8, kappa_p = 9 * K3 / 4, K3_p = kappa_p - mu_p / 3;
        if (parity) {
            if (!(K3_p > 0) || !(3 * K3_p - 2 * mu_p < 2 * (3 * K3_p + mu_p)) ||
                !(3 * K3_p - 2 * mu_p > -2 * (3 * K3_p + mu_p)))
                throw ConfigError(w, fmt::format("--parity peridem: the equivalent 2D "
                                                 "material (mu' = {:.4g}, kappa' = {:.4g} Pa)"
                                                 " is not a stable isotropic solid",
                                                 mu_p, kappa_p));
            m.erase("youngs_modulus");
            m["bulk_modulus"] = K3_p;
            m["shear_modulus"] = mu_p;
            lps_parity = true;
            if (Gc > 0) {
                const double d_peridem = 3 * G3 + std::pow(0.75, 4) * (K3 - 5 * G3 / 3);
                const double d_pdgrain =
                    6 * mu_p / M_PI + 16 / (9 * M_PI * M_PI) * (kappa_p - 2 * mu_p);
                const double Gc_p = Gc * d_pdgrain / d_peridem;
                log.info("{}: --parity peridem: PDState in 2D as PeriDEM 0.2 computes it: "
                         "shear modulus {:.4g} -> {:.4g} Pa (15 G / 8), 2D bulk modulus "
                         "{:.4g} Pa (9 K / 4; plane strain K = {:.4g} Pa), Gc {:.4g} -> "
                         "{:.4g} J/m2 (same critical stretch)",
                         w, G3, mu_p, kappa_p, K3_p, Gc, Gc_p);
                Gc = Gc_p;
            }
        } else {
            m["poisson_ratio"] = nu;
            if (!lps_noted) {
                const double kappa_2d =
                    plane_strain_deck ? K3 + G3 / 3 : 9 * K3 * G3 / (3 * K3 + 4 * G3);
                log.info("{}: PDState is imported as pdgrain's consistent 2D LPS with the "
                         "deck's K and G. PeriDEM 0.2 uses the 3D LPS formulas in 2D, so its "
                         "grains are {:.2f}x as stiff in shear and {:.2f}x in bulk as these "
                         "(contacts and wave speeds differ); --parity peridem maps the "
                         "material to PeriDEM's (mu' = 15 G/8, kappa' = 9 K/4, Gc' keeping "
                         "s0)",
                         w, 15.0 / 8.0, 9 * K3 / 4 / kappa_2d);
                lps_noted = true;
            }
        }
    }

    void influence(const YAML::Node& mn, const std::string& w, const std::string& law, json& m) {
        const Log& log = im.log;
        const int inf =
            int_or(child(mn, "Influence_Function"), w + ".Influence_Function", "Type", 0, 0, 2);
        if (inf < 0 || inf > 2)
            throw ConfigError(
                w + ".Influence_Function.Type",
                fmt::format("{}: expected 0 (constant), 1 (linear) or 2 (gaussian)", inf));
        if (child(child(mn, "Influence_Function"), "Parameters"))
            log.warn("{}.Influence_Function.Parameters: ignored (pdgrain uses the normalised "
                     "default parameters; in the state-based law only the shape of J matters)",
                     w);
        if (law == "pmb") {
            if (inf != 0)
                log.warn("{}.Influence_Function.Type = {}: pdgrain's PMB law uses J = 1", w, inf);
        } else
            m["influence"] = inf == 0 ? "constant" : inf == 1 ? "linear" : "gaussian";
        if (auto bp = child(mn, "Bond_Potential"))
            if (num_or(bp, w + ".Bond_Potential", "Check_Sc_Factor", 1) != 1)
                log.warn("{}.Bond_Potential.Check_Sc_Factor: ignored (bonds break at s0)", w);
    }
};

/// One horizon per scene: all absolute, or all a multiple of each particle's h.
void read_discretization(Import& im, const std::vector<double>& horizon,
                         const std::vector<double>& ratio) {
    const auto& zones = im.zones;
    json& discretization = im.discretization;
    {
        const bool by_ratio = ratio[0] > 0;
        for (std::size_t k = 0; k < zones.size(); ++k) {
            const double v = by_ratio ? ratio[k] : horizon[k];
            const std::string key = fmt::format("Material.Zone_{}.{}", k + 1,
                                                by_ratio ? "Horizon_Mesh_Ratio" : "Horizon");
            if (!(v > 0))
                throw ConfigError(key, "missing or not positive (required)");
            if (std::abs(v - (by_ratio ? ratio[0] : horizon[0])) > 1e-12 * v)
                throw ConfigError(key, "differs from Zone_1's: a pdgrain scene has one horizon "
                                       "(absolute, or a multiple of each particle's h)");
        }
        discretization["mesh_size"] = 0.0; // filled below
        if (by_ratio)
            discretization["horizon_mesh_ratio"] = ratio[0]; // x each particle's h (spec 2.3)
        else
            discretization["horizon"] = horizon[0];
        discretization["bond_cutoff"] = "strict";
        // PeriDEM runs horizons below 2 h (compression_small_set: 0.4 mm at h = 0.215 mm): warn.
        discretization["small_horizon"] = "warn";
    }
}

} // namespace

void read_materials(Import& im) {
    const YAML::Node& R = im.R;
    auto& zones = im.zones;
    const int nz = im.nz;
    MaterialReader reader{im};
    std::vector<double> horizon(zones.size(), 0), ratio(zones.size(), 0);
    // Is_Plane_Strain of any material (read ahead: the 2D bulk modulus of the note depends on it)
    bool plane_strain_deck = false;
    if (const YAML::Node mats = R["Material"]; mats && mats.IsMap())
        for (auto it = mats.begin(); it != mats.end(); ++it)
            if (it->second.IsMap() && it->second["Is_Plane_Strain"] &&
                it->second["Is_Plane_Strain"].as<std::string>() == "true")
                plane_strain_deck = true;
    std::vector<YAML::Node> mat_nodes(zones.size());
    for (int k = 1; k <= nz; ++k) {
        reader.read(k, mat_nodes, plane_strain_deck);
        horizon[static_cast<std::size_t>(k - 1)] = reader.horizon;
        ratio[static_cast<std::size_t>(k - 1)] = reader.ratio;
    }
    read_discretization(im, horizon, ratio);
}

} // namespace pd::pipeline::peridem
