// SPDX-License-Identifier: MIT
// Checked reads and unit-tagged writes of pd-file datasets (internal to lib/store/model_io*.cpp).
#pragma once

#include "core/errors.hpp"
#include "h5/file.hpp"
#include "model/model.hpp"
#include "store/schema.hpp"

#include <cmath>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

namespace pd::store::detail {

using h5::dims_t;

template <class T>
void put(h5::File& f, const std::string& p, const std::vector<T>& v, const dims_t& dims,
         const char* unit) {
    f.write(p, v, dims);
    f.set_attr(p, "unit", unit);
}

template <class T>
void put_scalar(h5::File& f, const std::string& p, T v, const char* unit) {
    f.write_scalar(p, v);
    f.set_attr(p, "unit", unit);
}

/// Reads `p` and checks its shape against `want` (0 in `want` = any extent).
template <class T>
std::vector<T> get(const h5::File& f, const std::string& p, const dims_t& want) {
    if (!f.exists(p))
        throw SchemaError(f.name(), p, "missing dataset");
    // The shape first: nothing is allocated for a dataset of the wrong shape (a huge declared
    // one included); the read itself refuses a size the file cannot hold (h5::File::read).
    const dims_t got = f.shape(p);
    bool ok = got.size() == want.size();
    for (std::size_t i = 0; ok && i < want.size(); ++i)
        ok = want[i] == 0 || want[i] == got[i];
    if (!ok) {
        auto fmt_dims = [](const dims_t& d) {
            std::string s = "(";
            for (std::size_t i = 0; i < d.size(); ++i)
                s += (i ? ", " : "") + (d[i] ? std::to_string(d[i]) : std::string("any"));
            return s + (d.size() == 1 ? ",)" : ")");
        };
        throw SchemaError(f.name(), p,
                          fmt::format("shape {}, expected {} (pd-file {})", fmt_dims(got),
                                      fmt_dims(want), schema_version));
    }
    auto v = f.read<T>(p);
    if constexpr (std::is_floating_point_v<T>) {
        for (std::size_t i = 0; i < v.size(); ++i)
            if (!std::isfinite(v[i]))
                throw SchemaError(f.name(), p, fmt::format("entry {} is not finite", i));
    }
    return v;
}

template <class T>
T get_scalar(const h5::File& f, const std::string& p) {
    if (!f.exists(p))
        throw SchemaError(f.name(), p, "missing dataset");
    const T v = f.read_scalar<T>(p);
    if constexpr (std::is_floating_point_v<T>)
        if (!std::isfinite(v))
            throw SchemaError(f.name(), p, fmt::format("{} is not finite", v));
    return v;
}

/// `v` in [lo, hi] (a physical scalar of a material or the solver).
inline void require_between(const h5::File& f, const std::string& p, double v, double lo, double hi,
                            const char* what) {
    if (!(v >= lo && v <= hi))
        throw SchemaError(f.name(), p,
                          fmt::format("{} outside [{:g}, {:g}] ({})", v, lo, hi, what));
}

/// Contact and wall groups index a groups x groups law table: the scene's range.
constexpr std::int32_t max_group = 1000;

template <class T>
void require_range(const h5::File& f, const std::string& p, const std::vector<T>& v, T lo, T hi) {
    for (std::size_t i = 0; i < v.size(); ++i)
        if (v[i] < lo || v[i] >= hi)
            throw SchemaError(f.name(), p,
                              fmt::format("entry {} = {} outside [{}, {})", i, v[i], lo, hi));
}

inline const char* law_name(model::Law l) {
    return l == model::Law::lps ? "lps" : l == model::Law::rnp ? "rnp" : "pmb";
}

inline const char* influence_name(model::Influence f) {
    return f == model::Influence::linear     ? "linear"
           : f == model::Influence::gaussian ? "gaussian"
                                             : "constant";
}

/// Each bond once in each direction (no node twice in a row, none bonded to itself, j in the
/// row of i means i in the row of j), else SchemaError naming /bonds/neighbor; the whole list.
void check_bond_pairs(const h5::File& f, const std::vector<std::int64_t>& offsets,
                      const std::vector<std::int32_t>& neighbor);

} // namespace pd::store::detail
