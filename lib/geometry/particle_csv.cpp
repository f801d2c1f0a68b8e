// SPDX-License-Identifier: MIT
// The particle CSV format of packing.hpp: x, y, z, r, orientation, shape per row, an optional
// header, '#' comments and blank lines skipped; written with 17 significant digits.
#include "core/errors.hpp"
#include "core/files.hpp"
#include "geometry/packing.hpp"

#include <fmt/format.h>

#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <string_view>

namespace pd::geometry {

namespace {
std::string_view trim(std::string_view s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front())))
        s.remove_prefix(1);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back())))
        s.remove_suffix(1);
    return s;
}

/// Splits a CSV row into numbers; false if a field is not a number (`out` then holds the fields
/// before it).
bool parse_row(std::string_view line, std::vector<double>& out) {
    out.clear();
    for (;;) {
        const auto comma = line.find(',');
        const std::string_view field = trim(line.substr(0, comma));
        double v = 0;
        const char* end = field.data() + field.size();
        const auto [ptr, ec] = std::from_chars(field.data(), end, v);
        if (field.empty() || ec != std::errc() || ptr != end)
            return false;
        out.push_back(v);
        if (comma == std::string_view::npos)
            return true;
        line.remove_prefix(comma + 1);
    }
}
} // namespace

std::vector<Grain> read_particle_csv(const std::string& path) {
    note_input("particle file", path);
    std::ifstream in(path);
    if (!in)
        throw InputError(fmt::format("cannot open particle file '{}'", path));
    std::vector<Grain> g;
    std::string line;
    std::vector<double> v;
    bool first = true;
    std::size_t offset = 0; // of the line's first byte in the file
    for (std::size_t no = 1; std::getline(in, line); ++no, offset += line.size() + 1) {
        const std::string_view t = trim(line);
        if (t.empty() || t.front() == '#')
            continue;
        const bool ok = parse_row(t, v);
        if (!ok && first) { // header
            first = false;
            continue;
        }
        first = false;
        // The message names the place, never the content: the file may be anything but a
        // particle CSV (a path gone wrong), and its bytes are not ours to print.
        if (!ok)
            throw InputError(fmt::format("{}:{} (byte {} of the file): expected 6 comma-separated "
                                         "numbers x, y, z, r, orientation, shape; field {} is not "
                                         "a number",
                                         path, no, offset, v.size() + 1));
        if (v.size() != 6)
            throw InputError(fmt::format("{}:{} (byte {} of the file): expected 6 comma-separated "
                                         "numbers x, y, z, r, orientation, shape; found {}",
                                         path, no, offset, v.size()));
        const double shape = v[5];
        if (!(v[3] > 0) || !std::isfinite(v[3]))
            throw InputError(fmt::format("{}:{}: radius {} must be > 0", path, no, v[3]));
        if (!(shape >= 0) || shape != std::floor(shape) || shape > 2e9)
            throw InputError(
                fmt::format("{}:{}: shape {} must be an integer index >= 0", path, no, shape));
        for (int k = 0; k < 5; ++k)
            if (!std::isfinite(v[static_cast<std::size_t>(k)]))
                throw InputError(fmt::format("{}:{}: values must be finite", path, no));
        g.push_back(Grain{{v[0], v[1], v[2]}, v[3], v[4], static_cast<std::int32_t>(shape)});
    }
    return g;
}

void write_particle_csv(const std::string& path, const std::vector<Grain>& grains) {
    std::ofstream out(path);
    if (!out)
        throw InputError(fmt::format("cannot write particle file '{}'", path));
    out << "x,y,z,r,orientation,shape\n";
    for (const auto& x : grains)
        out << fmt::format("{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{}\n", x.center[0], x.center[1],
                           x.center[2], x.radius, x.orientation, x.shape);
    if (!out)
        throw InputError(fmt::format("error writing particle file '{}'", path));
}

} // namespace pd::geometry
