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
#include <map>
#include <memory>
#include <string>

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

/// The force and moment series of one kind of reaction (rigid walls or reaction bodies).
struct ReactionSeries {
    const store::Series* force = nullptr;
    const store::Series* moment = nullptr;
};

/// Looks up `names` (force, moment) with 3 * count components each; `missing` and `what` word the
/// errors ("missing, but <missing>", "expected 3 * <count> <what>"). Empty when count is 0.
ReactionSeries reaction_series(const h5::File& f,
                               const std::map<std::string, store::Series>& series,
                               const std::array<const char*, 2>& names, std::size_t count,
                               const std::string& missing, const char* what) {
    const std::string obs = store::path::observables;
    ReactionSeries r;
    const store::Series** found[2] = {&r.force, &r.moment};
    for (std::size_t k = 0; k < names.size() && count > 0; ++k) {
        const std::string name = names[k];
        auto it = series.find(name);
        if (it == series.end())
            throw SchemaError(f.name(), obs + "/" + name, "missing, but " + missing);
        const auto& s = it->second;
        if (s.components != static_cast<int>(3 * count) ||
            s.value.size() != s.step.size() * 3 * count)
            throw SchemaError(f.name(), obs + "/" + name + "/value",
                              fmt::format("has {} values per row, expected 3 * {} {}", s.components,
                                          count, what));
        *found[k] = &s;
    }
    return r;
}

/// The columns of one reaction: disp, force, moment (x, y, z each), the normal force (walls
/// only), the force per stress_length (when > 0).
void header_columns(std::string& header, const std::string& prefix, bool normal,
                    double stress_length) {
    static const char* const axis[] = {"x", "y", "z"};
    for (const char* what : {"disp", "force", "moment"})
        for (const char* a : axis)
            header += fmt::format(",{}_{}_{}", prefix, what, a);
    if (normal)
        header += fmt::format(",{}_normal_force", prefix);
    if (stress_length > 0)
        for (const char* a : axis)
            header += fmt::format(",{}_stress_{}", prefix, a);
}

void add3(std::string& line, const double* v) {
    for (int d = 0; d < 3; ++d)
        line += fmt::format(",{:.17g}", v[d]);
}

void add_stress(std::string& line, const double* fk, double stress_length) {
    if (stress_length > 0)
        for (int d = 0; d < 3; ++d)
            line += fmt::format(",{:.17g}", fk[d] / stress_length);
}

/// Wall w's columns at time t: its imposed displacement, force, moment, normal force (planes).
void wall_columns(std::string& line, const model::Wall& w, double t, const double* fk,
                  const double* mk, double stress_length) {
    double rate = 0;
    const double T = model::wall_time(w, t, &rate); // its motion's time function
    const double disp[3] = {w.velocity[0] * T, w.velocity[1] * T, w.velocity[2] * T};
    add3(line, disp);
    add3(line, fk);
    add3(line, mk);
    if (w.shape == model::WallShape::plane)
        line += fmt::format(",{:.17g}",
                            fk[0] * w.normal[0] + fk[1] * w.normal[1] + fk[2] * w.normal[2]);
    else
        line += ",";
    add_stress(line, fk, stress_length);
}

/// Body b's columns at time t: its prescribed mean displacement, force, moment.
void body_columns(std::string& line, const model::Model& m, std::size_t b, double t,
                  const double* fk, const double* mk, double stress_length) {
    const auto u = body_displacement(m, b, t);
    add3(line, u.data());
    add3(line, fk);
    add3(line, mk);
    add_stress(line, fk, stress_length);
}

} // namespace

std::size_t write_walls_csv(const h5::File& f, const model::Model& m, const std::string& csv_path,
                            double stress_length) {
    const auto series = store::read_observables(f);
    const std::string obs = store::path::observables;
    const auto nw = m.walls.size();
    const auto walls = reaction_series(f, series, {"wall_force", "wall_moment"}, nw,
                                       fmt::format("the file has {} wall(s)", nw), "walls");
    if (nw > 0 && walls.moment->step != walls.force->step)
        throw SchemaError(f.name(), obs + "/wall_moment/step", "differs from wall_force/step");
    // Meshed walls: the fixed or driven bodies' reactions.
    const auto bodies = store::read_reaction_bodies(f);
    const auto nr = bodies.size();
    const auto body = reaction_series(f, series, {"body_force", "body_moment"}, nr,
                                      fmt::format("body_force/body lists {} bodies", nr), "bodies");
    for (auto b : bodies)
        if (b < 0 || static_cast<std::size_t>(b) >= m.bodies.num())
            throw SchemaError(f.name(), obs + "/body_force/body",
                              fmt::format("lists body {}, the file has {}", b, m.bodies.num()));
    if (nr > 0 && (body.moment->step != body.force->step ||
                   (nw > 0 && body.force->step != walls.force->step)))
        throw SchemaError(f.name(), obs + "/body_moment/step",
                          "differs from body_force/step or wall_force/step");
    if (nw == 0 && nr == 0)
        throw SchemaError(f.name(), obs,
                          "has no reactions: no rigid wall and no fixed or driven body");
    const store::Series* rows = nw > 0 ? walls.force : body.force;

    std::string header = "step,time";
    for (std::size_t k = 0; k < nw; ++k)
        header_columns(header, fmt::format("wall_{}", k), true, stress_length);
    for (auto b : bodies)
        header_columns(header, fmt::format("body_{}", b), false, stress_length);

    auto out = open_output(csv_path);
    fmt::print(out.get(), "{}\n", header);
    std::string line;
    for (std::size_t r = 0; r < rows->step.size(); ++r) {
        const double t = rows->time[r];
        line = fmt::format("{},{:.17g}", rows->step[r], t);
        for (std::size_t k = 0; k < nw; ++k)
            wall_columns(line, m.walls[k], t, walls.force->value.data() + r * 3 * nw + 3 * k,
                         walls.moment->value.data() + r * 3 * nw + 3 * k, stress_length);
        for (std::size_t k = 0; k < nr; ++k)
            body_columns(line, m, static_cast<std::size_t>(bodies[k]), t,
                         body.force->value.data() + r * 3 * nr + 3 * k,
                         body.moment->value.data() + r * 3 * nr + 3 * k, stress_length);
        line += '\n';
        if (std::fputs(line.c_str(), out.get()) < 0)
            throw InputError(fmt::format("{}: write failed (disk full?)", csv_path));
    }
    if (std::fflush(out.get()) != 0)
        throw InputError(fmt::format("{}: write failed (disk full?)", csv_path));
    return rows->step.size();
}

} // namespace pd::post
