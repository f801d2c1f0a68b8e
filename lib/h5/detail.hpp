// SPDX-License-Identifier: MIT
// HDF5 types and extents of C++ values (internal to lib/h5/*.cpp).
#pragma once

#include "h5/file.hpp"

#include <hdf5.h>

#include <cstdint>
#include <functional>
#include <numeric>
#include <string>
#include <type_traits>
#include <vector>

/// The element types every typed File member is instantiated for (each .cpp applies its own
/// PD_H5_INSTANTIATE to this list, so the list is kept in one place).
#define PD_H5_ELEMENT_TYPES(X)                                                                     \
    X(double) X(float) X(std::int32_t) X(std::int64_t) X(std::uint8_t) X(std::uint64_t)

namespace pd::h5::detail {

template <class T>
hid_t native() {
    if constexpr (std::is_same_v<T, double>)
        return H5T_NATIVE_DOUBLE;
    else if constexpr (std::is_same_v<T, float>)
        return H5T_NATIVE_FLOAT;
    else if constexpr (std::is_same_v<T, std::int32_t>)
        return H5T_NATIVE_INT32;
    else if constexpr (std::is_same_v<T, std::int64_t>)
        return H5T_NATIVE_INT64;
    else if constexpr (std::is_same_v<T, std::uint8_t>)
        return H5T_NATIVE_UINT8;
    else
        return H5T_NATIVE_UINT64;
}

inline std::vector<hsize_t> to_h(const dims_t& d) {
    return {d.begin(), d.end()};
}

inline std::uint64_t product(const dims_t& d) {
    return std::accumulate(d.begin(), d.end(), std::uint64_t{1}, std::multiplies<>{});
}

inline Handle vlen_string_type() {
    Handle t(H5Tcopy(H5T_C_S1));
    H5Tset_size(t.get(), H5T_VARIABLE);
    H5Tset_cset(t.get(), H5T_CSET_UTF8);
    return t;
}

/// Throws Error naming the first object of the open file `file` (named `name`) that points
/// outside it: an external or user-defined link, a virtual dataset, external raw storage
/// (confined.cpp).
void refuse_links_elsewhere(hid_t file, const std::string& name);

} // namespace pd::h5::detail
