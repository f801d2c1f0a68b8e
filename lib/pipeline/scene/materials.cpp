// SPDX-License-Identifier: MIT
#include "core/errors.hpp"
#include "model/pmb.hpp"
#include "pipeline/scene/build.hpp"

#include <cctype>
#include <cmath>

namespace pd::pipeline::scene {

namespace {

/// Elastic constants of material `mat` (its law set) from the keys of `*it`.
void elastic_constants(json::const_iterator it, const std::string& w, const model::Model& m,
                       model::Material& mat) {
    // Elastic constants: two of E, K, G, nu (spec 1.2-1.3); a bond-based law (pmb, rnp)
    // fixes nu, so E alone is enough there and a pair must agree with the law's nu.
    const double nu_law = mat.law == model::Law::rnp ? 0.25
                          : mat.law == model::Law::pmb
                              ? model::pmb_poisson_ratio(m.dimension, m.planar)
                              : -2.0;
    const bool hE = it->contains("youngs_modulus"), hK = it->contains("bulk_modulus"),
               hG = it->contains("shear_modulus"), hn = it->contains("poisson_ratio");
    const int given = hE + hK + hG + hn;
    double E = hE ? positive(*it, w, "youngs_modulus", 0) : 0;
    const double K = hK ? positive(*it, w, "bulk_modulus", 0) : 0;
    const double G = hG ? positive(*it, w, "shear_modulus", 0) : 0;
    double nu = hn ? number(*it, w, "poisson_ratio", 0) : nu_law;
    if (hn && !(nu > -1 && nu < 0.5))
        throw ConfigError(w + ".poisson_ratio", "must be in (-1, 0.5)");
    if (given == 1 && hE && nu_law > -2) {
        // E with the law's nu
    } else if (given != 2) {
        throw ConfigError(w, nu_law > -2 ? "give youngs_modulus, or two of youngs_modulus, "
                                           "bulk_modulus, shear_modulus, poisson_ratio"
                                         : "give two of youngs_modulus, bulk_modulus, "
                                           "shear_modulus, poisson_ratio");
    } else if (hE && hG) {
        nu = E / (2 * G) - 1;
    } else if (hE && hK) {
        nu = (3 * K - E) / (6 * K);
    } else if (hK && hG) {
        nu = (3 * K - 2 * G) / (2 * (3 * K + G));
        E = 9 * K * G / (3 * K + G);
    } else if (hK && hn) {
        E = 3 * K * (1 - 2 * nu);
    } else if (hG && hn) {
        E = 2 * G * (1 + nu);
    }
    if (!(E > 0) || !(nu > -1 && nu < 0.5))
        throw ConfigError(w, fmt::format("the elastic constants give E = {:.4g} Pa, nu = "
                                         "{:.4g}: not a stable isotropic solid",
                                         E, nu));
    if (nu_law > -2 && std::abs(nu - nu_law) > 1e-6)
        throw ConfigError(
            w, fmt::format("the {} law fixes nu = {:.4g} ({}), the constants "
                           "given imply nu = {:.4g}",
                           mat.law == model::Law::rnp ? "RNP" : "bond-based PMB", nu_law,
                           mat.law == model::Law::rnp                ? "spec 1.4"
                           : m.planar == model::Planar::plane_stress ? "2D plane stress"
                                                                     : "plane strain / 3D",
                           nu));
    mat.youngs_modulus = E;
    // Beyond any solid (diamond: E ~ 1.2e12 Pa, osmium 2.2e4 kg/m3): such values overflow
    // the contact stiffness, the stable time step and the energies.
    if (!(E <= 1e15))
        throw ConfigError(w + (hE ? ".youngs_modulus" : ".bulk_modulus"),
                          fmt::format("E = {:g} Pa is above 1e15 Pa", E));
    if (mat.density > 1e6)
        throw ConfigError(w + ".density",
                          fmt::format("{:g} kg/m3 is above 1e6 kg/m3", mat.density));
    mat.poisson_ratio = nu_law > -2 ? nu_law : nu;
}

/// "flaws": {"law": "weibull", "modulus": m, "seed": k} (model/flaws.hpp); absent = none.
void parse_flaws(const json& mj, const std::string& w, model::Material& mat) {
    if (!mj.contains("flaws"))
        return;
    const std::string wf = w + ".flaws";
    const json& j = mj["flaws"];
    if (!j.is_object())
        throw ConfigError(wf, "expected an object {\"law\": \"weibull\", \"modulus\": m, "
                              "\"seed\": k}");
    check_keys(j, wf, {"law", "modulus", "seed", "length"});
    if (text(j, wf, "law", "weibull", {"weibull", "none"}) == "none")
        return;
    mat.flaw_modulus = positive(j, wf, "modulus", 0, true);
    if (!(mat.flaw_modulus >= 0.5 && mat.flaw_modulus <= 1000))
        throw ConfigError(wf + ".modulus",
                          fmt::format("{:g} is outside [0.5, 1000]", mat.flaw_modulus));
    const double seed = number(j, wf, "seed", 0);
    if (!(seed >= 0 && seed < 9e15) || seed != std::floor(seed))
        throw ConfigError(wf + ".seed", "expected an integer >= 0");
    mat.flaw_seed = static_cast<std::int64_t>(seed);
    mat.flaw_length = number(j, wf, "length", 0);
    if (!(mat.flaw_length >= 0 && mat.flaw_length < 1e10))
        throw ConfigError(wf + ".length", "must be >= 0 m (0: one factor per bond)");
    if (!(mat.fracture_energy > 0))
        throw ConfigError(wf, "the material is unbreakable (fracture_energy 0): no flaws");
    if (mat.law == model::Law::rnp || mat.break_in_compression)
        throw ConfigError(wf, "flaws apply to the PMB and LPS laws breaking in tension only "
                              "(not law \"rnp\", not break_in_compression)");
}

model::Material parse_material(json::const_iterator it, const model::Model& m) {
    const std::string w = "materials." + it.key();
    check_keys(*it, w,
               {"law", "density", "youngs_modulus", "bulk_modulus", "shear_modulus",
                "poisson_ratio", "fracture_energy", "fracture_toughness", "influence",
                "break_in_compression", "flaws"});
    model::Material mat;
    mat.name = it.key();
    for (char ch : mat.name)
        if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '_'))
            throw ConfigError(w, "material names may hold letters, digits and '_' only");
    const auto law = text(*it, w, "law", "pmb", {"pmb", "lps", "rnp"});
    mat.law = law == "lps" ? model::Law::lps : law == "rnp" ? model::Law::rnp : model::Law::pmb;
    const auto inf = text(*it, w, "influence", mat.law == model::Law::pmb ? "constant" : "linear",
                          {"constant", "linear", "gaussian"});
    mat.influence = inf == "linear"     ? model::Influence::linear
                    : inf == "gaussian" ? model::Influence::gaussian
                                        : model::Influence::constant;
    if (mat.law == model::Law::pmb && mat.influence != model::Influence::constant)
        throw ConfigError(w + ".influence", "the PMB law uses J = 1 (constant); influence "
                                            "functions apply to laws \"lps\" and \"rnp\"");
    mat.density = positive(*it, w, "density", 0, true);
    elastic_constants(it, w, m, mat);
    // Fracture: Gc, or KIc with Gc = KIc^2 / E (spec 1.2).
    if (it->contains("fracture_energy") && it->contains("fracture_toughness"))
        throw ConfigError(w, "give fracture_energy or fracture_toughness, not both");
    mat.fracture_energy =
        it->contains("fracture_toughness")
            ? std::pow(positive(*it, w, "fracture_toughness", 0), 2) / mat.youngs_modulus
            : number(*it, w, "fracture_energy", 0);
    if (mat.fracture_energy < 0)
        throw ConfigError(w + ".fracture_energy", "must be >= 0 (0 = unbreakable)");
    if (mat.law == model::Law::rnp && !(mat.fracture_energy > 0))
        throw ConfigError(w + ".fracture_energy", "the RNP law needs Gc > 0");
    // PeriDEM compatibility (spec 1.3: |s| > s0): bonds break in compression too.
    mat.break_in_compression = boolean(*it, w, "break_in_compression", false);
    parse_flaws(*it, w, mat);
    return mat;
}

} // namespace

void parse_materials(SceneBuild& s) {
    const json& root = s.root;
    model::Model& m = s.m;
    auto& material_index = s.material_index;
    // Materials.
    if (!root.contains("materials") || !root["materials"].is_object() || root["materials"].empty())
        throw ConfigError("materials", "missing: give at least one material by name");
    for (auto it = root["materials"].begin(); it != root["materials"].end(); ++it) {
        model::Material mat = parse_material(it, m);
        material_index[mat.name] = static_cast<std::int32_t>(m.materials.size());
        m.materials.push_back(mat);
    }
}

} // namespace pd::pipeline::scene
