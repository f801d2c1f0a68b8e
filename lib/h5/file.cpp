// SPDX-License-Identifier: MIT
#include "h5/file.hpp"

#include "h5/detail.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cstring>
#include <functional>
#include <numeric>
#include <sys/stat.h>

namespace pd::h5 {

namespace {

struct Stack {
    std::string text;
    bool disk_full = false;
};

herr_t walk_cb(unsigned n, const H5E_error2_t* e, void* data) {
    auto* s = static_cast<Stack*>(data);
    if (n < 3 && e->desc && *e->desc)
        s->text += (s->text.empty() ? "" : "; ") + std::string(e->desc);
    // The system's reason, at the bottom of the stack: a full disk is said as such.
    if (e->desc && (std::strstr(e->desc, "errno = 28,") || std::strstr(e->desc, "No space left")))
        s->disk_full = true;
    return 0;
}

std::string error_stack() {
    Stack s;
    H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, walk_cb, &s);
    H5Eclear2(H5E_DEFAULT);
    return s.disk_full ? "disk full: No space left on device; " + s.text : s.text;
}

struct SilenceHdf5 {
    SilenceHdf5() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }
};
const SilenceHdf5 silence_once;

std::string parent_of(const std::string& path) {
    auto p = path.find_last_of('/');
    return p == 0 || p == std::string::npos ? "/" : path.substr(0, p);
}

} // namespace

using namespace detail;

Error::Error(const std::string& file, const std::string& path, const std::string& what)
    : InputError(fmt::format("{}: {}: {}", file, path, what)) {}

Handle& Handle::operator=(Handle&& o) noexcept {
    if (this != &o) {
        this->~Handle();
        id_ = o.id_;
        o.id_ = -1;
    }
    return *this;
}

Handle::~Handle() {
    if (id_ < 0)
        return;
    switch (H5Iget_type(id_)) {
    case H5I_FILE:
        H5Fclose(id_);
        break;
    case H5I_GROUP:
        H5Gclose(id_);
        break;
    case H5I_DATASET:
        H5Dclose(id_);
        break;
    case H5I_DATASPACE:
        H5Sclose(id_);
        break;
    case H5I_DATATYPE:
        H5Tclose(id_);
        break;
    case H5I_ATTR:
        H5Aclose(id_);
        break;
    case H5I_GENPROP_LST:
        H5Pclose(id_);
        break;
    default:
        break;
    }
    id_ = -1;
}

bool is_hdf5(const std::string& name) {
    htri_t r = H5Fis_hdf5(name.c_str());
    H5Eclear2(H5E_DEFAULT);
    return r > 0;
}

void File::check_read_size(hid d, const std::string& path, double elements,
                           std::size_t bytes_each) const {
    const double bytes = elements * static_cast<double>(bytes_each);
    if (bytes <= 64.0 * 1024 * 1024)
        return;
    const double stored = static_cast<double>(H5Dget_storage_size(d));
    hsize_t file_size = 0;
    H5Fget_filesize(id_.get(), &file_size);
    if (bytes <= 1100.0 * std::min(stored, static_cast<double>(file_size)))
        return;
    throw Error(name_, path,
                fmt::format("declares {:.4g} values ({:.4g} bytes) but stores {:.4g} bytes in a "
                            "file of {} bytes: refused before allocating (a damaged or forged "
                            "file)",
                            elements, bytes, stored, file_size));
}

void File::check_storage(const std::string& path) const {
    Handle d = open_dataset(path);
    double elements = 1;
    for (auto n : shape(path))
        elements *= static_cast<double>(n);
    check_read_size(d.get(), path, elements, type_size(path));
}

void File::fail(const std::string& path, const std::string& what) const {
    std::string stack = error_stack();
    throw Error(name_, path, stack.empty() ? what : what + " (" + stack + ")");
}

File::File(const std::string& name, Mode mode, const void* mpi_comm)
    : name_(name) {
    // pdgrain's own lock first: a writer takes it, a reader is refused while another process
    // writes. Under MPI-IO rank 0 decides and every rank raises the same error (collective).
    auto take_lock = [&] {
        if (mode == Mode::read)
            FileLock::check_free(name);
        else
            lock_ = FileLock::acquire(name);
    };
    Handle fapl(H5Pcreate(H5P_FILE_ACCESS));
    xfer_ = Handle(H5Pcreate(H5P_DATASET_XFER));
    // A writer takes no HDF5 file lock (pdgrain's own lock above keeps a second pdgrain writer
    // out): h5py and other readers can open the file while pd-solve writes it (issue 28; HDF5
    // 1.10 locks the whole file for a writer, "unable to lock file, errno = 11"). Each frame is
    // flushed whole; README "Watching a run" gives the reader's way.
    if (mode != Mode::read && H5Pset_file_locking(fapl.get(), false, true) < 0)
        fail("/", "cannot set the file locking property");
    if (mpi_comm) {
        MPI_Comm comm = *static_cast<const MPI_Comm*>(mpi_comm);
        MPI_Comm_rank(comm, &rank_);
        std::string why;
        if (rank_ == 0) {
            try {
                take_lock();
            } catch (const InputError& e) {
                why = e.what();
            }
        }
        int len = static_cast<int>(why.size());
        MPI_Bcast(&len, 1, MPI_INT, 0, comm);
        why.resize(static_cast<std::size_t>(len));
        MPI_Bcast(why.data(), len, MPI_CHAR, 0, comm);
        if (len > 0)
            throw InputError(why);
        // Every other rank of a writing run holds the lock too, shared: a rank that outlives
        // rank 0 (killed alone) keeps the file locked until it has gone.
        if (mode != Mode::read && rank_ != 0)
            lock_ = FileLock::share(name);
        if (H5Pset_fapl_mpio(fapl.get(), comm, MPI_INFO_NULL) < 0)
            fail("/", "cannot set the MPI-IO driver");
        H5Pset_dxpl_mpio(xfer_.get(), H5FD_MPIO_COLLECTIVE);
        parallel_ = true;
    } else {
        take_lock();
    }
    hid_t id = -1;
    if (mode == Mode::create_truncate) {
        id = H5Fcreate(name.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get());
        if (id < 0)
            fail("/", "cannot create the file");
    } else {
        if (!is_hdf5(name))
            throw Error(name, "/", "not an HDF5 file, or unreadable (missing or truncated?)");
        id = H5Fopen(name.c_str(), mode == Mode::read ? H5F_ACC_RDONLY : H5F_ACC_RDWR, fapl.get());
        if (id < 0)
            fail("/", mode == Mode::read ? "cannot open for reading" : "cannot open for writing");
    }
    id_ = Handle(id);
    if (mode != Mode::create_truncate)
        refuse_links_elsewhere(id, name_);
    struct stat st {};
    if (::stat(name_.c_str(), &st) == 0) {
        dev_ = static_cast<std::uint64_t>(st.st_dev);
        ino_ = static_cast<std::uint64_t>(st.st_ino);
    }
}

bool File::still_named() const {
    struct stat st {};
    return ::stat(name_.c_str(), &st) == 0 && static_cast<std::uint64_t>(st.st_dev) == dev_ &&
           static_cast<std::uint64_t>(st.st_ino) == ino_;
}

void File::flush() {
    if (H5Fflush(id_.get(), H5F_SCOPE_LOCAL) < 0)
        fail("/", "flush failed (disk full?)");
}

void File::close() {
    if (!id_.valid())
        return;
    flush();
    const hid id = id_.release(); // not closed again by the destructor, even if this fails
    const bool ok = H5Fclose(id) >= 0;
    lock_ = FileLock();
    if (!ok)
        fail("/", "close failed (disk full?)");
}

bool File::exists(const std::string& path) const {
    if (path == "/")
        return true;
    std::string cur;
    std::size_t start = 1;
    while (start <= path.size()) {
        auto end = path.find('/', start);
        if (end == std::string::npos)
            end = path.size();
        cur += "/" + path.substr(start, end - start);
        htri_t r = H5Lexists(id_.get(), cur.c_str(), H5P_DEFAULT);
        if (r <= 0) {
            H5Eclear2(H5E_DEFAULT);
            return false;
        }
        start = end + 1;
    }
    return true;
}

bool File::is_group(const std::string& path) const {
    if (!exists(path))
        return false;
    H5O_info_t info;
    if (H5Oget_info_by_name(id_.get(), path.c_str(), &info, H5P_DEFAULT) < 0)
        fail(path, "cannot stat object");
    return info.type == H5O_TYPE_GROUP;
}

void File::create_group(const std::string& path) {
    if (exists(path))
        return;
    Handle lcpl(H5Pcreate(H5P_LINK_CREATE));
    H5Pset_create_intermediate_group(lcpl.get(), 1);
    Handle g(H5Gcreate2(id_.get(), path.c_str(), lcpl.get(), H5P_DEFAULT, H5P_DEFAULT));
    if (!g.valid())
        fail(path, "cannot create group");
}

void File::ensure_parent(const std::string& path) {
    create_group(parent_of(path));
}

std::vector<std::string> File::list(const std::string& group) const {
    Handle g(H5Gopen2(id_.get(), group.c_str(), H5P_DEFAULT));
    if (!g.valid())
        fail(group, "missing group");
    H5G_info_t info;
    H5Gget_info(g.get(), &info);
    std::vector<std::string> names;
    for (hsize_t i = 0; i < info.nlinks; ++i) {
        ssize_t n = H5Lget_name_by_idx(g.get(), ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0,
                                       H5P_DEFAULT);
        std::string s(static_cast<std::size_t>(n), '\0');
        H5Lget_name_by_idx(g.get(), ".", H5_INDEX_NAME, H5_ITER_INC, i, s.data(), s.size() + 1,
                           H5P_DEFAULT);
        names.push_back(s);
    }
    std::sort(names.begin(), names.end());
    return names;
}

void File::remove(const std::string& path) {
    if (exists(path) && H5Ldelete(id_.get(), path.c_str(), H5P_DEFAULT) < 0)
        fail(path, "cannot remove");
}

void File::hard_link(const std::string& target, const std::string& link) {
    ensure_parent(link);
    remove(link);
    if (H5Lcreate_hard(id_.get(), target.c_str(), id_.get(), link.c_str(), H5P_DEFAULT,
                       H5P_DEFAULT) < 0)
        fail(link, "cannot link to " + target);
}

Handle File::open_object(const std::string& path) const {
    if (!exists(path))
        throw Error(name_, path, "missing");
    Handle o(H5Oopen(id_.get(), path.c_str(), H5P_DEFAULT));
    if (!o.valid())
        fail(path, "cannot open");
    return o;
}

Handle File::open_dataset(const std::string& path) const {
    if (!exists(path))
        throw Error(name_, path, "missing dataset");
    Handle d(H5Dopen2(id_.get(), path.c_str(), H5P_DEFAULT));
    if (!d.valid())
        fail(path, "not a dataset, or unreadable");
    return d;
}

dims_t File::shape(const std::string& path) const {
    Handle d = open_dataset(path);
    Handle s(H5Dget_space(d.get()));
    int rank = H5Sget_simple_extent_ndims(s.get());
    if (rank < 0)
        fail(path, "cannot read shape");
    std::vector<hsize_t> h(static_cast<std::size_t>(rank));
    H5Sget_simple_extent_dims(s.get(), h.data(), nullptr);
    return {h.begin(), h.end()};
}

char File::type_class(const std::string& path) const {
    Handle d = open_dataset(path);
    Handle t(H5Dget_type(d.get()));
    switch (H5Tget_class(t.get())) {
    case H5T_FLOAT:
        return 'f';
    case H5T_INTEGER:
        return H5Tget_sign(t.get()) == H5T_SGN_NONE ? 'u' : 'i';
    case H5T_STRING:
        return 's';
    default:
        return '?';
    }
}

std::size_t File::type_size(const std::string& path) const {
    Handle d = open_dataset(path);
    Handle t(H5Dget_type(d.get()));
    return H5Tget_size(t.get());
}

template <Element T>
void File::write(const std::string& path, std::span<const T> data, const dims_t& dims) {
    // Every rank takes part; under MPI-IO rank 0's data is written.
    const bool writes = !parallel_ || rank_ == 0;
    write_runs(path, data, dims, writes && !dims.empty() ? runs_t{{0, dims[0]}} : runs_t{});
}

void File::root_only(hid file_space, hid mem_space) const {
    if (parallel_ && rank_ != 0) { // rank 0 writes, the others take part
        H5Sselect_none(file_space);
        H5Sselect_none(mem_space);
    }
}

namespace {
/// Selects rows `runs` of axis `axis` (earlier axes at `lead`, later ones whole) in `space`.
void select_runs(hid_t space, const runs_t& runs, const std::vector<hsize_t>& lead) {
    const int rank = H5Sget_simple_extent_ndims(space);
    std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
    H5Sget_simple_extent_dims(space, dims.data(), nullptr);
    H5Sselect_none(space);
    std::vector<hsize_t> start(dims.size(), 0), count = dims;
    for (std::size_t a = 0; a < lead.size(); ++a) {
        start[a] = lead[a];
        count[a] = 1;
    }
    const std::size_t axis = lead.size();
    for (const auto& r : runs) {
        if (r[1] <= r[0])
            continue;
        start[axis] = r[0];
        count[axis] = r[1] - r[0];
        H5Sselect_hyperslab(space, H5S_SELECT_OR, start.data(), nullptr, count.data(), nullptr);
    }
}
} // namespace

template <Element T>
void File::write_runs(const std::string& path, std::span<const T> full, const dims_t& dims,
                      const runs_t& runs) {
    if (product(dims) != full.size())
        throw InternalError(fmt::format("{}: {}: {} values for shape of {}", name_, path,
                                        full.size(), product(dims)));
    ensure_parent(path);
    remove(path);
    auto h = to_h(dims);
    Handle fs(H5Screate_simple(static_cast<int>(h.size()), h.data(), nullptr));
    Handle d(H5Dcreate2(id_.get(), path.c_str(), native<T>(), fs.get(), H5P_DEFAULT, H5P_DEFAULT,
                        H5P_DEFAULT));
    if (!d.valid())
        fail(path, "cannot create dataset");
    if (full.empty())
        return;
    Handle ms(H5Screate_simple(static_cast<int>(h.size()), h.data(), nullptr));
    select_runs(fs.get(), runs, {});
    select_runs(ms.get(), runs, {});
    if (H5Dwrite(d.get(), native<T>(), ms.get(), fs.get(), xfer_.get(), full.data()) < 0)
        fail(path, "write failed");
}

template <Element T>
void File::append_runs(const std::string& path, std::span<const T> full, const runs_t& runs) {
    auto sh = shape(path);
    const std::uint64_t row = sh[0];
    resize_rows(path, row + 1);
    Handle d = open_dataset(path);
    dims_t inner(sh.begin() + 1, sh.end());
    if (product(inner) != full.size())
        throw InternalError(fmt::format("{}: {}: {} values for an entry of {}", name_, path,
                                        full.size(), product(inner)));
    auto hi = to_h(inner);
    Handle fs(H5Dget_space(d.get()));
    Handle ms(H5Screate_simple(static_cast<int>(hi.size()), hi.data(), nullptr));
    select_runs(fs.get(), runs, {row});
    select_runs(ms.get(), runs, {});
    if (H5Dwrite(d.get(), native<T>(), ms.get(), fs.get(), xfer_.get(), full.data()) < 0)
        fail(path, "write failed");
}

template <Element T>
void File::write_scalar(const std::string& path, T value) {
    ensure_parent(path);
    remove(path);
    Handle space(H5Screate(H5S_SCALAR));
    Handle d(H5Dcreate2(id_.get(), path.c_str(), native<T>(), space.get(), H5P_DEFAULT, H5P_DEFAULT,
                        H5P_DEFAULT));
    Handle fs(H5Screate(H5S_SCALAR)), ms(H5Screate(H5S_SCALAR));
    root_only(fs.get(), ms.get());
    if (!d.valid() || H5Dwrite(d.get(), native<T>(), ms.get(), fs.get(), xfer_.get(), &value) < 0)
        fail(path, "cannot write scalar");
}

void File::write_string(const std::string& path, const std::string& value) {
    ensure_parent(path);
    remove(path);
    Handle t = vlen_string_type();
    Handle space(H5Screate(H5S_SCALAR));
    Handle d(H5Dcreate2(id_.get(), path.c_str(), t.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT,
                        H5P_DEFAULT));
    const char* p = value.c_str();
    if (!d.valid() || H5Dwrite(d.get(), t.get(), H5S_ALL, H5S_ALL, xfer_.get(), &p) < 0)
        fail(path, "cannot write string");
}

template <Element T>
std::vector<T> File::read(const std::string& path, dims_t* dims) const {
    Handle d = open_dataset(path);
    dims_t sh = shape(path);
    if (type_class(path) == 's')
        throw Error(name_, path, "holds strings, expected numbers");
    double elements = 1;
    for (auto n : sh)
        elements *= static_cast<double>(n);
    check_read_size(d.get(), path, elements, sizeof(T));
    std::vector<T> out(product(sh));
    if (!out.empty() &&
        H5Dread(d.get(), native<T>(), H5S_ALL, H5S_ALL, xfer_.get(), out.data()) < 0)
        fail(path, "read failed");
    if (dims)
        *dims = sh;
    return out;
}

template <Element T>
T File::read_scalar(const std::string& path) const {
    dims_t sh;
    auto v = read<T>(path, &sh);
    if (v.size() != 1)
        throw Error(name_, path, fmt::format("expected a scalar, found {} values", v.size()));
    return v[0];
}

std::string File::read_string(const std::string& path) const {
    Handle d = open_dataset(path);
    Handle ft(H5Dget_type(d.get()));
    if (H5Tget_class(ft.get()) != H5T_STRING)
        throw Error(name_, path, "expected a string dataset");
    {
        Handle sp(H5Dget_space(d.get()));
        if (H5Sget_simple_extent_npoints(sp.get()) != 1)
            throw Error(name_, path, "expected one string, found an array");
    }
    if (H5Tis_variable_str(ft.get()) > 0) {
        Handle t = vlen_string_type();
        char* p = nullptr;
        if (H5Dread(d.get(), t.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, &p) < 0)
            fail(path, "read failed");
        std::string s = p ? p : "";
        H5free_memory(p);
        return s;
    }
    std::size_t n = H5Tget_size(ft.get());
    std::string s(n, '\0');
    if (H5Dread(d.get(), ft.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, s.data()) < 0)
        fail(path, "read failed");
    s.resize(std::strlen(s.c_str()));
    return s;
}

#define PD_H5_INSTANTIATE(T)                                                                       \
    template void File::write<T>(const std::string&, std::span<const T>, const dims_t&);           \
    template void File::write_scalar<T>(const std::string&, T);                                    \
    template void File::write_runs<T>(const std::string&, std::span<const T>, const dims_t&,       \
                                      const runs_t&);                                              \
    template void File::append_runs<T>(const std::string&, std::span<const T>, const runs_t&);     \
    template std::vector<T> File::read<T>(const std::string&, dims_t*) const;                      \
    template T File::read_scalar<T>(const std::string&) const;

PD_H5_ELEMENT_TYPES(PD_H5_INSTANTIATE)

} // namespace pd::h5
