// SPDX-License-Identifier: MIT
// observables.csv writer (see csv.hpp).
#include "post/csv.hpp"

#include "core/errors.hpp"
#include "h5/file.hpp"
#include "post/text_out.hpp"
#include "store/frames.hpp"
#include "store/schema.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <vector>

namespace pd::post {

namespace {

/// Column names of a series with `components` values per row. `per_item`: the series is
/// (rows, items, 3), as the wall reactions are, even with a single item.
void add_columns(std::string& header, const std::string& name, int components, bool per_item) {
    static const char* const axis[] = {"_x", "_y", "_z"};
    if (components == 1) {
        header += "," + name;
    } else if (components % 3 == 0) {
        for (int c = 0; c < components; ++c) {
            header += "," + name;
            if (per_item)
                header += fmt::format("_{}", c / 3);
            header += axis[c % 3];
        }
    } else {
        for (int c = 0; c < components; ++c)
            header += fmt::format(",{}_{}", name, c);
    }
}

} // namespace

std::size_t write_observables_csv(const h5::File& f, const std::string& csv_path) {
    const auto series = store::read_observables(f);
    const auto& list = store::observable_list();
    const std::string obs = store::path::observables;
    if (list.empty())
        throw InternalError("store::observable_list() is empty");

    // Column order: the standard list, then the other series in name order.
    std::vector<std::string> names;
    for (const auto& info : list) {
        auto it = series.find(info.name);
        if (it == series.end() && !info.required)
            continue; // a file from before the series was added
        if (it == series.end())
            throw SchemaError(f.name(), obs + "/" + info.name, "missing observable series");
        if (it->second.components != info.components)
            throw SchemaError(f.name(), obs + "/" + info.name + "/value",
                              fmt::format("has {} components per row, expected {}",
                                          it->second.components, info.components));
        names.push_back(info.name);
    }
    for (const auto& [name, s] : series)
        if (std::find(names.begin(), names.end(), name) == names.end())
            names.push_back(name);

    // Every series shares the step/time of the first one (hard links in the file).
    const store::Series& first = series.at(list.front().name);
    const std::size_t rows = first.step.size();
    std::string header = "step,time";
    for (const auto& name : names) {
        const auto& s = series.at(name);
        if (s.step.size() != rows || s.step != first.step)
            throw SchemaError(f.name(), obs + "/" + name + "/step",
                              fmt::format("has {} rows, not the {} steps of {}", s.step.size(),
                                          rows, list.front().name));
        if (s.value.size() != rows * static_cast<std::size_t>(s.components))
            throw SchemaError(
                f.name(), obs + "/" + name + "/value",
                fmt::format("has {} values for {} rows of {}", s.value.size(), rows, s.components));
        const bool standard = std::any_of(list.begin(), list.end(),
                                          [&](const auto& info) { return info.name == name; });
        add_columns(header, name, s.components, !standard);
    }

    auto out = open_output(csv_path);
    fmt::print(out.get(), "{}\n", header);
    std::string line;
    for (std::size_t r = 0; r < rows; ++r) {
        line = fmt::format("{},{:.17g}", first.step[r], first.time[r]);
        for (const auto& name : names) {
            const auto& s = series.at(name);
            const auto c = static_cast<std::size_t>(s.components);
            for (std::size_t k = 0; k < c; ++k)
                line += fmt::format(",{:.17g}", s.value[r * c + k]);
        }
        line += '\n';
        if (std::fputs(line.c_str(), out.get()) < 0)
            throw InputError(fmt::format("{}: write failed (disk full?)", csv_path));
    }
    if (std::fflush(out.get()) != 0)
        throw InputError(fmt::format("{}: write failed (disk full?)", csv_path));
    return rows;
}

} // namespace pd::post
