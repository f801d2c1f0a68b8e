// SPDX-License-Identifier: MIT
#include "core/errors.hpp"
#include "core/files.hpp"
#include "pipeline/peridem/import.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <random>
#include <sstream>

namespace pd::pipeline::peridem {

namespace {

constexpr double pi = std::numbers::pi;

/// The particle CSV (zone, x, y, z, r[, o]), when a zone takes its particles from it.
void read_csv(const Import& im, std::vector<std::array<double, 6>>& rows, bool& with_orient,
              const std::string& csv_key) {
    const Deck& d = im.d;
    const YAML::Node& R = im.R;
    const int nz = im.nz;
    const auto& zones = im.zones;
    if (std::any_of(zones.begin(), zones.end(), [](const Zone& z) { return !z.from_geom; })) {
        const YAML::Node pg = R["Particle_Generation"];
        if (!pg || !child(pg, "From_File"))
            throw ConfigError(csv_key, "missing: the particle CSV (zone, x, y, z, r[, o])");
        const auto type = str_or(pg, "Particle_Generation", "File_Data_Type", "loc_rad");
        if (type != "loc_rad" && type != "loc_rad_orient")
            throw ConfigError("Particle_Generation.File_Data_Type",
                              "'" + type + "': expected loc_rad or loc_rad_orient");
        with_orient = type == "loc_rad_orient";
        const auto file = deck_file(d, csv_key, str_or(pg, "Particle_Generation", "From_File", ""));
        note_input(csv_key, file);
        std::ifstream in(file);
        if (!in)
            throw ConfigError(csv_key, file + ": cannot read");
        std::string line;
        std::size_t ln = 0;
        while (std::getline(in, line)) {
            ++ln;
            for (char& c : line)
                if (c == ',')
                    c = ' ';
            std::istringstream ls(line);
            std::vector<double> v;
            std::string tok;
            bool numeric = true;
            while (ls >> tok) {
                try {
                    std::size_t used = 0;
                    v.push_back(std::stod(tok, &used));
                    numeric = numeric && used == tok.size();
                } catch (...) {
                    numeric = false;
                }
            }
            if (v.empty() && numeric)
                continue; // blank
            if (!numeric) {
                if (ln == 1)
                    continue; // header
                throw ConfigError(csv_key, fmt::format("{} line {}: not numbers", file, ln));
            }
            const std::size_t need = with_orient ? 6 : 5;
            if (v.size() < need)
                throw ConfigError(csv_key,
                                  fmt::format("{} line {}: expected {} columns (zone, x, "
                                              "y, z, r{}), found {}",
                                              file, ln, need, with_orient ? ", o" : "", v.size()));
            if (!(v[4] > 0))
                throw ConfigError(
                    csv_key, fmt::format("{} line {}: radius {} must be positive", file, ln, v[4]));
            if (v[0] < 0 || v[0] >= nz || v[0] != std::floor(v[0]))
                throw ConfigError(csv_key, fmt::format("{} line {}: zone {} is not in [0, {})",
                                                       file, ln, v[0], nz));
            rows.push_back({v[0], v[1], v[2], v[3], v[4], with_orient ? v[5] : 0.0});
        }
    }
}

} // namespace

void read_particles(Import& im) {
    const YAML::Node& R = im.R;
    const Log& log = im.log;
    const int dim = im.dim;
    const std::uint32_t seed = im.seed;
    auto& zones = im.zones;
    auto& parts = im.parts;
    auto& wall_ids = im.wall_ids;
    // ---- Particles, zone by zone (global ids cumulative over zones, CSV order inside).
    std::vector<std::array<double, 6>> rows; // zone, x, y, z, r, o
    bool with_orient = true;
    std::string csv_key = "Particle_Generation.From_File";
    read_csv(im, rows, with_orient, csv_key);
    const bool two_particle = str_or(R["Particle"], "Particle", "Test_Name", "") == "two_particle";
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> angle(0.0, 2 * pi);
    if (!with_orient && !two_particle)
        log.warn("Particle_Generation.File_Data_Type = loc_rad: orientations drawn uniformly in "
                 "[0, 2 pi) with seed {} (not PeriDEM's draws)",
                 seed);
    for (auto& z : zones) {
        if (z.from_geom) {
            Particle p;
            p.zone = z.k;
            p.scaled = false;
            z.particles.push_back(parts.size());
            parts.push_back(p);
            continue;
        }
        for (const auto& row : rows) {
            if (static_cast<int>(row[0]) != z.k - 1)
                continue;
            Particle p;
            p.zone = z.k;
            p.x = {row[1], row[2], dim == 3 ? row[3] : 0.0};
            p.r = row[4];
            p.o = with_orient    ? row[5]
                  : two_particle ? static_cast<double>(parts.size()) * pi
                                 : angle(rng);
            z.particles.push_back(parts.size());
            parts.push_back(p);
        }
        if (z.particles.empty())
            log.warn("Particle.Zone_{}: no particle of this zone in the CSV", z.k);
    }
    if (parts.empty())
        throw ConfigError(csv_key, "no particle was placed");
    for (const auto& z : zones)
        if (z.wall)
            wall_ids.insert(wall_ids.end(), z.particles.begin(), z.particles.end());
}

} // namespace pd::pipeline::peridem
