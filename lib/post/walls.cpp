// SPDX-License-Identifier: MIT
// walls.csv writer (see walls.hpp).
#include "post/walls.hpp"

#include "core/errors.hpp"
#include "h5/file.hpp"
#include "model/functions.hpp"
#include "post/text_out.hpp"
#include "store/frames.hpp"
#include "store/schema.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <memory>

namespace pd::post {

namespace {

/// Mean displacement (volume-weighted, 3) of body b at time t as its displacement conditions
/// prescribe it (0 where none does: a fixed body).
std::array<double, 3> body_displacement(const model::Model& m, std::size_t b, double t) {
    std::array<double, 3> mean{0, 0, 0};
    double vol = 0;
    std::vector<double> u(3 * static_cast<std::size_t>(m.bodies.end(b) - m.bodies.begin(b)), 0.0);
    const auto first = m.bodies.begin(b), last = m.bodies.end(b);
    for (const auto& c : m.loading.conditions) {
        if (c.is_force)
            continue;
        std::array<double, 4> box{1e300, -1e300, 1e300, -1e300};
        for (auto i : c.nodes) {
            const double* X = &m.nodes.x0[3 * static_cast<std::size_t>(i)];
            box = {std::min(box[0], X[0]), std::max(box[1], X[0]), std::min(box[2], X[1]),
                   std::max(box[3], X[1])};
        }
        for (auto i : c.nodes)
            if (i >= first && i < last)
                model::prescribed_displacement(c, &m.nodes.x0[3 * static_cast<std::size_t>(i)], box,
                                               t, &u[3 * static_cast<std::size_t>(i - first)]);
    }
    for (auto i = first; i < last; ++i) {
        const double v = m.nodes.volume[static_cast<std::size_t>(i)];
        vol += v;
        for (std::size_t d = 0; d < 3; ++d)
            mean[d] += v * u[3 * static_cast<std::size_t>(i - first) + d];
    }
    for (double& x : mean)
        x /= vol > 0 ? vol : 1.0;
    return mean;
}

} // namespace

std::size_t write_walls_csv(const h5::File& f, const model::Model& m, const std::string& csv_path,
                            double stress_length) {
    const auto series = store::read_observables(f);
    const std::string obs = store::path::observables;
    const auto nw = m.walls.size();
    const store::Series* force = nullptr;
    const store::Series* moment = nullptr;
    for (const char* name : {"wall_force", "wall_moment"}) {
        if (nw == 0)
            break;
        auto it = series.find(name);
        if (it == series.end())
            throw SchemaError(f.name(), obs + "/" + name,
                              fmt::format("missing, but the file has {} wall(s)", nw));
        const auto& s = it->second;
        if (s.components != static_cast<int>(3 * nw) || s.value.size() != s.step.size() * 3 * nw)
            throw SchemaError(
                f.name(), obs + "/" + name + "/value",
                fmt::format("has {} values per row, expected 3 * {} walls", s.components, nw));
        (std::string(name) == "wall_force" ? force : moment) = &s;
    }
    if (nw > 0 && moment->step != force->step)
        throw SchemaError(f.name(), obs + "/wall_moment/step", "differs from wall_force/step");
    // Meshed walls: the fixed or driven bodies' reactions.
    const auto bodies = store::read_reaction_bodies(f);
    const auto nr = bodies.size();
    const store::Series* bforce = nullptr;
    const store::Series* bmoment = nullptr;
    for (const char* name : {"body_force", "body_moment"}) {
        if (nr == 0)
            break;
        auto it = series.find(name);
        if (it == series.end())
            throw SchemaError(f.name(), obs + "/" + name,
                              fmt::format("missing, but body_force/body lists {} bodies", nr));
        const auto& s = it->second;
        if (s.components != static_cast<int>(3 * nr) || s.value.size() != s.step.size() * 3 * nr)
            throw SchemaError(
                f.name(), obs + "/" + name + "/value",
                fmt::format("has {} values per row, expected 3 * {} bodies", s.components, nr));
        (std::string(name) == "body_force" ? bforce : bmoment) = &s;
    }
    for (auto b : bodies)
        if (b < 0 || static_cast<std::size_t>(b) >= m.bodies.num())
            throw SchemaError(f.name(), obs + "/body_force/body",
                              fmt::format("lists body {}, the file has {}", b, m.bodies.num()));
    if (nr > 0 && (bmoment->step != bforce->step || (nw > 0 && bforce->step != force->step)))
        throw SchemaError(f.name(), obs + "/body_moment/step",
                          "differs from body_force/step or wall_force/step");
    if (nw == 0 && nr == 0)
        throw SchemaError(f.name(), obs,
                          "has no reactions: no rigid wall and no fixed or driven body");
    const store::Series* rows = nw > 0 ? force : bforce;

    std::string header = "step,time";
    static const char* const axis[] = {"x", "y", "z"};
    for (std::size_t k = 0; k < nw; ++k) {
        for (const char* what : {"disp", "force", "moment"})
            for (const char* a : axis)
                header += fmt::format(",wall_{}_{}_{}", k, what, a);
        header += fmt::format(",wall_{}_normal_force", k);
        if (stress_length > 0)
            for (const char* a : axis)
                header += fmt::format(",wall_{}_stress_{}", k, a);
    }
    for (auto b : bodies) {
        for (const char* what : {"disp", "force", "moment"})
            for (const char* a : axis)
                header += fmt::format(",body_{}_{}_{}", b, what, a);
        if (stress_length > 0)
            for (const char* a : axis)
                header += fmt::format(",body_{}_stress_{}", b, a);
    }

    auto out = open_output(csv_path);
    fmt::print(out.get(), "{}\n", header);
    std::string line;
    for (std::size_t r = 0; r < rows->step.size(); ++r) {
        const double t = rows->time[r];
        line = fmt::format("{},{:.17g}", rows->step[r], t);
        for (std::size_t k = 0; k < nw; ++k) {
            const auto& w = m.walls[k];
            const double* fk = force->value.data() + r * 3 * nw + 3 * k;
            const double* mk = moment->value.data() + r * 3 * nw + 3 * k;
            double rate = 0;
            const double T = model::wall_time(w, t, &rate); // its motion's time function
            for (int d = 0; d < 3; ++d)
                line += fmt::format(",{:.17g}", w.velocity[d] * T);
            for (int d = 0; d < 3; ++d)
                line += fmt::format(",{:.17g}", fk[d]);
            for (int d = 0; d < 3; ++d)
                line += fmt::format(",{:.17g}", mk[d]);
            if (w.shape == model::WallShape::plane)
                line += fmt::format(",{:.17g}", fk[0] * w.normal[0] + fk[1] * w.normal[1] +
                                                    fk[2] * w.normal[2]);
            else
                line += ",";
            if (stress_length > 0)
                for (int d = 0; d < 3; ++d)
                    line += fmt::format(",{:.17g}", fk[d] / stress_length);
        }
        for (std::size_t k = 0; k < nr; ++k) {
            const auto u = body_displacement(m, static_cast<std::size_t>(bodies[k]), t);
            const double* fk = bforce->value.data() + r * 3 * nr + 3 * k;
            const double* mk = bmoment->value.data() + r * 3 * nr + 3 * k;
            for (int d = 0; d < 3; ++d)
                line += fmt::format(",{:.17g}", u[static_cast<std::size_t>(d)]);
            for (int d = 0; d < 3; ++d)
                line += fmt::format(",{:.17g}", fk[d]);
            for (int d = 0; d < 3; ++d)
                line += fmt::format(",{:.17g}", mk[d]);
            if (stress_length > 0)
                for (int d = 0; d < 3; ++d)
                    line += fmt::format(",{:.17g}", fk[d] / stress_length);
        }
        line += '\n';
        if (std::fputs(line.c_str(), out.get()) < 0)
            throw InputError(fmt::format("{}: write failed (disk full?)", csv_path));
    }
    if (std::fflush(out.get()) != 0)
        throw InputError(fmt::format("{}: write failed (disk full?)", csv_path));
    return rows->step.size();
}

} // namespace pd::post
