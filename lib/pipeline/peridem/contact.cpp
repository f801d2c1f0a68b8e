// SPDX-License-Identifier: MIT
#include "core/errors.hpp"
#include "pipeline/peridem/import.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

namespace pd::pipeline::peridem {

namespace {

/// PeriDEM 0.2's particle damping of zones (i, j) (--parity peridem): beta_n = Beta_n_Factor
/// (-2 ln eps / sqrt(pi^2 + ln^2 eps)) and kappa the harmonic mean 2 a b / (a + b) of the deck's
/// bulk moduli (PeriDEM's DEMModel::setupContact: util::equivalentMass, which is 2 a b / (a + b),
/// so kappa = K for one material); pdgrain's A = beta_n sqrt(kappa).
double approach_damping(const YAML::Node& n, const std::string& w, const Import& im,
                        std::pair<int, int> ij) {
    const double eps = num_or(n, w, "Epsilon", 1), log_e = std::log(eps);
    const double beta =
        num_or(n, w, "Beta_n_Factor", 1) * (-2 * log_e / std::sqrt(M_PI * M_PI + log_e * log_e));
    const double ki = im.zone_bulk.at(static_cast<std::size_t>(ij.first - 1));
    const double kj = im.zone_bulk.at(static_cast<std::size_t>(ij.second - 1));
    if (!(eps > 0 && eps <= 1))
        throw ConfigError(w + ".Epsilon", "must be in (0, 1]");
    return beta > 1e-8 ? beta * std::sqrt(2 * ki * kj / (ki + kj)) : 0.0;
}

/// One Contact.Zone_<i><j> block -> a scene contact law.
json contact_law(const YAML::Node& n, const std::string& w, const Import& im,
                 std::pair<int, int> ij, bool& beta_warned) {
    const Log& log = im.log;
    json law = json::object();
    if (child(n, "Contact_Radius"))
        law["radius"] = num_or(n, w, "Contact_Radius", 0);
    else if (child(n, "Contact_Radius_Factor"))
        law["radius_factor"] = num_or(n, w, "Contact_Radius_Factor", 0);
    else
        throw ConfigError(w, "no Contact_Radius_Factor or Contact_Radius (PeriDEM "
                             "would use R_c = 0: no contact)");
    const double kn = num_or(n, w, "Kn", 0) * num_or(n, w, "Kn_Factor", 1);
    // Kn 0 (or missing): PeriDEM applies no contact force; pdgrain's stiffness 0 is the same
    // (the pair does not interact; issue 28: imported as "auto" before, a driven plate pushed on
    // its container from step 0).
    law["stiffness"] = kn > 0 ? kn : 0.0;
    if (!(kn > 0))
        log.info("{}.Kn: missing or zero: no contact between these zones (as in PeriDEM)", w);
    if (flag_or(n, w, "Damping_On", true)) {
        if (!child(n, "Epsilon"))
            throw ConfigError(w + ".Epsilon", "required when Damping_On is true");
        law["restitution"] = num_or(n, w, "Epsilon", 1);
        if (im.parity) {
            // PeriDEM damps grains on approach (solver/terms/approach_damping.cpp), not on
            // unloading as pdgrain's restitution does.
            law["restitution"] = 1.0;
            law["approach_damping"] = approach_damping(n, w, im, ij);
            if (!beta_warned)
                log.info("{}: --parity peridem: damping as PeriDEM's (on approach, from "
                         "1.01 R_c, on the grains' centre nodes), not pdgrain's restitution",
                         w);
            beta_warned = true;
        } else if (!beta_warned && num_or(n, w, "Beta_n_Factor", 1) != 1) {
            log.info("{}.Beta_n_Factor: not used (pdgrain's damping achieves the "
                     "restitution Epsilon directly)",
                     w);
            beta_warned = true;
        }
    } else
        law["restitution"] = 1.0;
    law["friction"] = flag_or(n, w, "Friction_On", true) ? num_or(n, w, "Friction_Coeff", 0) : 0.0;
    return law;
}

bool zone_is_wall(const std::vector<Zone>& zones, int k) {
    for (const auto& z : zones)
        if (z.k == k)
            return z.wall;
    return false;
}

} // namespace

void read_contact(Import& im) {
    const YAML::Node& R = im.R;
    const Log& log = im.log;
    const bool single = im.single;
    const int nz = im.nz;
    const auto& zones = im.zones;
    json& contact = im.contact;
    // ---- Contact table (groups = zones - 1).
    if (!single) {
        const YAML::Node cb = R["Contact"];
        std::map<std::pair<int, int>, json> table;
        std::map<std::pair<int, int>, YAML::Node> raw;
        bool beta_warned = false;
        if (cb && cb.IsMap()) {
            // Copies first need their source: walk in deck order, resolving as we go.
            for (auto it = cb.begin(); it != cb.end(); ++it) {
                const auto key = it->first.as<std::string>();
                if (key.rfind("Zone_", 0) != 0) {
                    log.warn("Contact.{}: not a zone pair, ignored", key);
                    continue;
                }
                raw[zone_pair(key, "Contact", nz)] = it->second;
            }
            for (auto& [ij, node] : raw) {
                const std::string w = fmt::format("Contact.Zone_{}{}", ij.first, ij.second);
                YAML::Node n;
                n.reset(node);
                if (auto cp = child(n, "Copy_Contact_Data")) {
                    auto src = ints(n, w, "Copy_Contact_Data");
                    if (src.size() != 2)
                        throw ConfigError(w + ".Copy_Contact_Data", "expected [i, j]");
                    auto s = std::make_pair(std::min(src[0], src[1]), std::max(src[0], src[1]));
                    auto f = raw.find({static_cast<int>(s.first), static_cast<int>(s.second)});
                    if (f == raw.end())
                        throw ConfigError(w + ".Copy_Contact_Data", "no such contact pair");
                    n.reset(f->second);
                }
                table[ij] = contact_law(n, w, im, ij, beta_warned);
            }
        }
        std::set<int> used;
        for (const auto& z : zones)
            if (!z.particles.empty())
                used.insert(z.k);
        json pairs = json::array();
        for (int i : used)
            for (int j : used)
                if (j >= i) {
                    auto f = table.find({i, j});
                    if (f == table.end()) {
                        log.warn("Contact.Zone_{}{}: missing; pdgrain's default law applies "
                                 "(Kn auto, radius 0.95 h)",
                                 i, j);
                        continue;
                    }
                    json p = f->second;
                    p["groups"] = {i - 1, j - 1};
                    // PeriDEM never computes wall-wall contact (it skips pairs of wall
                    // particles): a fixed container and a driven plate do not push on each other.
                    if (zone_is_wall(zones, i) && zone_is_wall(zones, j) &&
                        !(p["stiffness"].is_number() && p["stiffness"].get<double>() == 0)) {
                        p["stiffness"] = 0.0;
                        log.info("Contact.Zone_{}{}: both zones are walls: no contact between "
                                 "them (PeriDEM skips wall-wall pairs)",
                                 i, j);
                    }
                    pairs.push_back(p);
                }
        if (!pairs.empty()) {
            for (auto it = pairs[0].begin(); it != pairs[0].end(); ++it)
                if (it.key() != "groups")
                    contact[it.key()] = *it;
            contact["pairs"] = pairs;
        }
    }
}

} // namespace pd::pipeline::peridem
