// SPDX-License-Identifier: MIT
// File: datasets read and written by rows, extendible along axis 0 (frames, observables).
#include "h5/detail.hpp"
#include "h5/file.hpp"

#include <hdf5.h>

namespace pd::h5 {

using namespace detail;

template <Element T>
std::vector<T> File::read_rows(const std::string& path, std::uint64_t row0,
                               std::uint64_t count) const {
    Handle d = open_dataset(path);
    dims_t sh = shape(path);
    if (sh.empty() || row0 + count > sh[0])
        throw Error(name_, path, fmt::format("rows [{}, {}) out of range", row0, row0 + count));
    auto start = std::vector<hsize_t>(sh.size(), 0);
    auto cnt = to_h(sh);
    start[0] = row0;
    cnt[0] = count;
    Handle fs(H5Dget_space(d.get()));
    H5Sselect_hyperslab(fs.get(), H5S_SELECT_SET, start.data(), nullptr, cnt.data(), nullptr);
    double elements = 1;
    for (auto n : cnt)
        elements *= static_cast<double>(n);
    check_read_size(d.get(), path, elements, sizeof(T));
    Handle ms(H5Screate_simple(static_cast<int>(cnt.size()), cnt.data(), nullptr));
    std::vector<T> out(product(dims_t(cnt.begin(), cnt.end())));
    if (!out.empty() &&
        H5Dread(d.get(), native<T>(), ms.get(), fs.get(), xfer_.get(), out.data()) < 0)
        fail(path, "read failed");
    return out;
}

template <Element T>
void File::create_extendible(const std::string& path, const dims_t& inner, std::uint64_t chunk_rows,
                             int deflate) {
    ensure_parent(path);
    remove(path);
    std::vector<hsize_t> cur{0}, max{H5S_UNLIMITED}, chunk{std::max<std::uint64_t>(1, chunk_rows)};
    for (auto n : inner) {
        cur.push_back(n);
        max.push_back(n);
        chunk.push_back(std::max<std::uint64_t>(1, n));
    }
    Handle space(H5Screate_simple(static_cast<int>(cur.size()), cur.data(), max.data()));
    Handle dcpl(H5Pcreate(H5P_DATASET_CREATE));
    H5Pset_chunk(dcpl.get(), static_cast<int>(chunk.size()), chunk.data());
    // Early: chunks are allocated when the dataset grows, which MPI-IO needs to append to a file
    // a serial run created (late allocation there: pwritev EINVAL and a damaged file).
    H5Pset_alloc_time(dcpl.get(), H5D_ALLOC_TIME_EARLY);
    if (deflate > 0 && H5Pset_deflate(dcpl.get(), static_cast<unsigned>(std::min(deflate, 9))) < 0)
        fail(path, "gzip compression is not available in this HDF5 build");
    Handle d(H5Dcreate2(id_.get(), path.c_str(), native<T>(), space.get(), H5P_DEFAULT, dcpl.get(),
                        H5P_DEFAULT));
    if (!d.valid())
        fail(path, "cannot create extendible dataset");
}

bool File::allocated_early(const std::string& path) const {
    Handle d = open_dataset(path);
    Handle dcpl(H5Dget_create_plist(d.get()));
    if (H5Pget_layout(dcpl.get()) != H5D_CHUNKED)
        return true;
    H5D_alloc_time_t t{};
    if (H5Pget_alloc_time(dcpl.get(), &t) < 0)
        fail(path, "cannot read the allocation time");
    return t == H5D_ALLOC_TIME_EARLY;
}

void File::reallocate_early(const std::string& path) {
    if (parallel_)
        throw InternalError(fmt::format("{}: {}: reallocate_early under MPI-IO", name_, path));
    Handle d = open_dataset(path);
    Handle dcpl(H5Dget_create_plist(d.get()));
    if (H5Pget_layout(dcpl.get()) != H5D_CHUNKED)
        return;
    H5Pset_alloc_time(dcpl.get(), H5D_ALLOC_TIME_EARLY);
    Handle type(H5Dget_type(d.get()));
    Handle space(H5Dget_space(d.get()));
    if (H5Tdetect_class(type.get(), H5T_VLEN) > 0 || H5Tis_variable_str(type.get()) > 0)
        fail(path, "reallocate_early: variable-length data are not supported");
    const int rank = H5Sget_simple_extent_ndims(space.get());
    std::vector<hsize_t> dims(static_cast<std::size_t>(std::max(rank, 0)));
    if (rank < 1 || H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr) < 0)
        fail(path, "reallocate_early: not a simple dataset");
    const std::string tmp = path + "__early";
    remove(tmp);
    Handle nd(H5Dcreate2(id_.get(), tmp.c_str(), type.get(), space.get(), H5P_DEFAULT, dcpl.get(),
                         H5P_DEFAULT));
    if (!nd.valid())
        fail(tmp, "cannot create");
    // Data, in blocks of rows (the frames of a long run do not fit in memory at once).
    std::size_t row_bytes = H5Tget_size(type.get());
    for (int k = 1; k < rank; ++k)
        row_bytes *= dims[static_cast<std::size_t>(k)];
    const hsize_t block = std::max<hsize_t>(1, (64u << 20) / std::max<std::size_t>(1, row_bytes));
    std::vector<unsigned char> buf;
    for (hsize_t r0 = 0; r0 < dims[0]; r0 += block) {
        std::vector<hsize_t> start(dims.size(), 0), cnt = dims;
        start[0] = r0;
        cnt[0] = std::min(block, dims[0] - r0);
        buf.resize(row_bytes * cnt[0]);
        Handle fs(H5Dget_space(d.get())), ns(H5Dget_space(nd.get()));
        Handle ms(H5Screate_simple(rank, cnt.data(), nullptr));
        H5Sselect_hyperslab(fs.get(), H5S_SELECT_SET, start.data(), nullptr, cnt.data(), nullptr);
        H5Sselect_hyperslab(ns.get(), H5S_SELECT_SET, start.data(), nullptr, cnt.data(), nullptr);
        if (H5Dread(d.get(), type.get(), ms.get(), fs.get(), H5P_DEFAULT, buf.data()) < 0)
            fail(path, "read failed");
        if (H5Dwrite(nd.get(), type.get(), ms.get(), ns.get(), H5P_DEFAULT, buf.data()) < 0)
            fail(tmp, "write failed");
    }
    // Attributes, with their own types (variable-length strings included).
    H5O_info_t info{};
    if (H5Oget_info(d.get(), &info) < 0)
        fail(path, "cannot read its attributes");
    for (hsize_t i = 0; i < info.num_attrs; ++i) {
        Handle a(
            H5Aopen_by_idx(d.get(), ".", H5_INDEX_NAME, H5_ITER_INC, i, H5P_DEFAULT, H5P_DEFAULT));
        const ssize_t len = H5Aget_name(a.get(), 0, nullptr);
        std::string an(static_cast<std::size_t>(std::max<ssize_t>(len, 0)), '\0');
        H5Aget_name(a.get(), an.size() + 1, an.data());
        Handle at(H5Aget_type(a.get()));
        Handle as(H5Aget_space(a.get()));
        const auto n =
            static_cast<std::size_t>(std::max<hssize_t>(1, H5Sget_simple_extent_npoints(as.get())));
        std::vector<unsigned char> ab(n * H5Tget_size(at.get()));
        if (H5Aread(a.get(), at.get(), ab.data()) < 0)
            fail(path, "cannot read attribute " + an);
        Handle na(H5Acreate2(nd.get(), an.c_str(), at.get(), as.get(), H5P_DEFAULT, H5P_DEFAULT));
        const bool ok = na.valid() && H5Awrite(na.get(), at.get(), ab.data()) >= 0;
        if (H5Tdetect_class(at.get(), H5T_VLEN) > 0 || H5Tis_variable_str(at.get()) > 0)
            H5Dvlen_reclaim(at.get(), as.get(), H5P_DEFAULT, ab.data());
        if (!ok)
            fail(tmp, "cannot write attribute " + an);
    }
    nd = Handle();
    d = Handle();
    if (H5Ldelete(id_.get(), path.c_str(), H5P_DEFAULT) < 0 ||
        H5Lmove(id_.get(), tmp.c_str(), id_.get(), path.c_str(), H5P_DEFAULT, H5P_DEFAULT) < 0)
        fail(path, "cannot replace it by its early-allocated copy");
}

void File::resize_rows(const std::string& path, std::uint64_t rows) {
    Handle d = open_dataset(path);
    auto sh = to_h(shape(path));
    sh[0] = rows;
    if (H5Dset_extent(d.get(), sh.data()) < 0)
        fail(path, "cannot resize (is it extendible?)");
}

template <Element T>
void File::write_rows(const std::string& path, std::span<const T> data, std::uint64_t row0,
                      std::uint64_t rows) {
    Handle d = open_dataset(path);
    auto sh = to_h(shape(path));
    if (row0 + rows > sh[0])
        throw InternalError(fmt::format("{}: {}: write past the end", name_, path));
    std::vector<hsize_t> start(sh.size(), 0), cnt = sh;
    start[0] = row0;
    cnt[0] = rows;
    std::uint64_t n = 1;
    for (auto c : cnt)
        n *= c;
    if (n != data.size())
        throw InternalError(
            fmt::format("{}: {}: {} values for {} rows", name_, path, data.size(), rows));
    Handle fs(H5Dget_space(d.get()));
    H5Sselect_hyperslab(fs.get(), H5S_SELECT_SET, start.data(), nullptr, cnt.data(), nullptr);
    Handle ms(H5Screate_simple(static_cast<int>(cnt.size()), cnt.data(), nullptr));
    root_only(fs.get(), ms.get());
    if (H5Dwrite(d.get(), native<T>(), ms.get(), fs.get(), xfer_.get(), data.data()) < 0)
        fail(path, "write failed");
}

template <Element T>
void File::append(const std::string& path, std::span<const T> data, std::uint64_t rows) {
    auto sh = shape(path);
    std::uint64_t row0 = sh[0];
    resize_rows(path, row0 + rows);
    write_rows(path, data, row0, rows);
}

#define PD_H5_INSTANTIATE(T)                                                                       \
    template std::vector<T> File::read_rows<T>(const std::string&, std::uint64_t, std::uint64_t)   \
        const;                                                                                     \
    template void File::create_extendible<T>(const std::string&, const dims_t&, std::uint64_t,     \
                                             int);                                                 \
    template void File::append<T>(const std::string&, std::span<const T>, std::uint64_t);          \
    template void File::write_rows<T>(const std::string&, std::span<const T>, std::uint64_t,       \
                                      std::uint64_t);

PD_H5_ELEMENT_TYPES(PD_H5_INSTANTIATE)

} // namespace pd::h5
