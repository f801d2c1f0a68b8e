// SPDX-License-Identifier: MIT
// walls.csv writer (see walls.hpp).
#include "post/walls.hpp"

#include "core/errors.hpp"
#include "h5/file.hpp"
#include "post/text_out.hpp"
#include "store/frames.hpp"
#include "store/schema.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <memory>

namespace pd::post {

std::size_t write_walls_csv(const h5::File& f, const model::Model& m, const std::string& csv_path,
                            double stress_length) {
    const auto series = store::read_observables(f);
    const std::string obs = store::path::observables;
    const auto nw = m.walls.size();
    const store::Series* force = nullptr;
    const store::Series* moment = nullptr;
    for (const char* name : {"wall_force", "wall_moment"}) {
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
    if (moment->step != force->step)
        throw SchemaError(f.name(), obs + "/wall_moment/step", "differs from wall_force/step");

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

    auto out = open_output(csv_path);
    fmt::print(out.get(), "{}\n", header);
    std::string line;
    for (std::size_t r = 0; r < force->step.size(); ++r) {
        const double t = force->time[r];
        line = fmt::format("{},{:.17g}", force->step[r], t);
        for (std::size_t k = 0; k < nw; ++k) {
            const auto& w = m.walls[k];
            const double* fk = force->value.data() + r * 3 * nw + 3 * k;
            const double* mk = moment->value.data() + r * 3 * nw + 3 * k;
            for (int d = 0; d < 3; ++d)
                line += fmt::format(",{:.17g}", w.velocity[d] * t);
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
        line += '\n';
        if (std::fputs(line.c_str(), out.get()) < 0)
            throw InputError(fmt::format("{}: write failed (disk full?)", csv_path));
    }
    if (std::fflush(out.get()) != 0)
        throw InputError(fmt::format("{}: write failed (disk full?)", csv_path));
    return force->step.size();
}

} // namespace pd::post
