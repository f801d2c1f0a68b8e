// SPDX-License-Identifier: MIT
// File: attributes (numbers, vectors, strings).
#include "h5/detail.hpp"
#include "h5/file.hpp"

#include <hdf5.h>

#include <cstring>
#include <utility>

namespace pd::h5 {

using namespace detail;

bool File::has_attr(const std::string& path, const std::string& name) const {
    if (!exists(path))
        return false;
    htri_t r = H5Aexists_by_name(id_.get(), path.c_str(), name.c_str(), H5P_DEFAULT);
    H5Eclear2(H5E_DEFAULT);
    return r > 0;
}

namespace {
void write_attr(hid_t obj, const std::string& name, hid_t type, hid_t space, const void* buf,
                const std::function<void(const std::string&)>& fail) {
    if (H5Aexists(obj, name.c_str()) > 0)
        H5Adelete(obj, name.c_str());
    Handle a(H5Acreate2(obj, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT));
    if (!a.valid() || H5Awrite(a.get(), type, buf) < 0)
        fail("cannot write attribute " + name);
}
} // namespace

template <Element T>
void File::set_attr(const std::string& path, const std::string& name, T value) {
    Handle o = open_object(path);
    Handle space(H5Screate(H5S_SCALAR));
    write_attr(o.get(), name, native<T>(), space.get(), &value,
               [&](const std::string& w) { fail(path, w); });
}

template <Element T>
void File::set_attr(const std::string& path, const std::string& name, const std::vector<T>& v) {
    Handle o = open_object(path);
    hsize_t n = v.size();
    Handle space(H5Screate_simple(1, &n, nullptr));
    write_attr(o.get(), name, native<T>(), space.get(), v.data(),
               [&](const std::string& w) { fail(path, w); });
}

void File::set_attr(const std::string& path, const std::string& name, const std::string& value) {
    Handle o = open_object(path);
    Handle t = vlen_string_type();
    Handle space(H5Screate(H5S_SCALAR));
    const char* p = value.c_str();
    write_attr(o.get(), name, t.get(), space.get(), &p,
               [&](const std::string& w) { fail(path, w); });
}

void File::set_attr(const std::string& path, const std::string& name,
                    const std::vector<std::string>& value) {
    Handle o = open_object(path);
    Handle t = vlen_string_type();
    hsize_t n = value.size();
    Handle space(H5Screate_simple(1, &n, nullptr));
    std::vector<const char*> p;
    for (auto& s : value)
        p.push_back(s.c_str());
    write_attr(o.get(), name, t.get(), space.get(), p.data(),
               [&](const std::string& w) { fail(path, w); });
}

void File::check_attr_size(hid a, const std::string& path, const std::string& name, double elements,
                           std::size_t bytes_each) const {
    const double bytes = elements * static_cast<double>(bytes_each);
    const double stored = static_cast<double>(H5Aget_storage_size(a));
    if (elements >= 0 && (bytes <= 64.0 * 1024 * 1024 || bytes <= 1100.0 * stored))
        return;
    throw Error(name_, path,
                fmt::format("attribute '{}' declares {:.4g} values but stores {:.4g} bytes: "
                            "refused before allocating (a damaged or forged file)",
                            name, elements, stored));
}

template <Element T>
std::vector<T> File::attr_vector(const std::string& path, const std::string& name) const {
    if (!has_attr(path, name))
        throw Error(name_, path, "missing attribute '" + name + "'");
    Handle a(H5Aopen_by_name(id_.get(), path.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT));
    Handle s(H5Aget_space(a.get()));
    hssize_t n = H5Sget_simple_extent_npoints(s.get());
    Handle ft(H5Aget_type(a.get()));
    if (H5Tget_class(ft.get()) == H5T_STRING)
        throw Error(name_, path, "attribute '" + name + "' holds a string, expected numbers");
    check_attr_size(a.get(), path, name, static_cast<double>(n), sizeof(T));
    std::vector<T> v(static_cast<std::size_t>(n));
    if (H5Aread(a.get(), native<T>(), v.data()) < 0)
        fail(path, "cannot read attribute " + name);
    return v;
}

template <Element T>
T File::attr(const std::string& path, const std::string& name) const {
    auto v = attr_vector<T>(path, name);
    if (v.size() != 1)
        throw Error(name_, path, "attribute '" + name + "' is not a scalar");
    return v[0];
}

std::string File::attr_string(const std::string& path, const std::string& name) const {
    auto v = attr_strings(path, name);
    if (v.size() != 1)
        throw Error(name_, path, "attribute '" + name + "' is an array, expected one string");
    return std::move(v[0]);
}

std::vector<std::string> File::attr_strings(const std::string& path,
                                            const std::string& name) const {
    if (!has_attr(path, name))
        throw Error(name_, path, "missing attribute '" + name + "'");
    Handle a(H5Aopen_by_name(id_.get(), path.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT));
    Handle ft(H5Aget_type(a.get()));
    if (H5Tget_class(ft.get()) != H5T_STRING)
        throw Error(name_, path, "attribute '" + name + "' is not a string");
    Handle sp(H5Aget_space(a.get()));
    const auto npoints = H5Sget_simple_extent_npoints(sp.get());
    check_attr_size(a.get(), path, name, static_cast<double>(npoints), sizeof(char*));
    const auto n = static_cast<std::size_t>(npoints);
    std::vector<std::string> v;
    v.reserve(n);
    if (H5Tis_variable_str(ft.get()) > 0) {
        Handle t = vlen_string_type();
        std::vector<char*> p(n, nullptr);
        if (H5Aread(a.get(), t.get(), p.data()) < 0)
            fail(path, "cannot read attribute " + name);
        for (auto* c : p) {
            v.emplace_back(c ? c : "");
            H5free_memory(c);
        }
        return v;
    }
    const std::size_t len = H5Tget_size(ft.get());
    std::vector<char> buf(n * len + 1, '\0');
    if (H5Aread(a.get(), ft.get(), buf.data()) < 0)
        fail(path, "cannot read attribute " + name);
    for (std::size_t k = 0; k < n; ++k)
        v.emplace_back(buf.data() + k * len, strnlen(buf.data() + k * len, len));
    return v;
}

std::vector<std::string> File::attr_names(const std::string& path) const {
    Handle o = open_object(path);
    H5O_info_t info;
    H5Oget_info(o.get(), &info);
    std::vector<std::string> names;
    for (hsize_t i = 0; i < info.num_attrs; ++i) {
        Handle a(
            H5Aopen_by_idx(o.get(), ".", H5_INDEX_NAME, H5_ITER_INC, i, H5P_DEFAULT, H5P_DEFAULT));
        ssize_t n = H5Aget_name(a.get(), 0, nullptr);
        std::string s(static_cast<std::size_t>(n), '\0');
        H5Aget_name(a.get(), s.size() + 1, s.data());
        names.push_back(s);
    }
    return names;
}

#define PD_H5_INSTANTIATE(T)                                                                       \
    template void File::set_attr<T>(const std::string&, const std::string&, T);                    \
    template void File::set_attr<T>(const std::string&, const std::string&,                        \
                                    const std::vector<T>&);                                        \
    template std::vector<T> File::attr_vector<T>(const std::string&, const std::string&) const;    \
    template T File::attr<T>(const std::string&, const std::string&) const;

PD_H5_ELEMENT_TYPES(PD_H5_INSTANTIATE)

} // namespace pd::h5
