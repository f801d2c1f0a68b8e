// SPDX-License-Identifier: MIT
// A small RAII layer over the HDF5 C API: files, groups, datasets (fixed and extendible along
// axis 0), attributes. Generic: it knows no pdgrain dataset path. Every HDF5 call is checked and
// a failure throws pd::h5::Error naming the file, the object path and the HDF5 error stack.
#pragma once

#include "core/errors.hpp"
#include "core/file_lock.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace pd::h5 {

using hid = std::int64_t; // hid_t without the HDF5 header
using dims_t = std::vector<std::uint64_t>;
/// Runs [begin, end) of rows: what one MPI rank writes of a node-indexed dataset.
using runs_t = std::vector<std::array<std::uint64_t, 2>>;

/// A failed HDF5 operation (unreadable or truncated file, missing object, full disk).
class Error : public InputError {
  public:
    Error(const std::string& file, const std::string& path, const std::string& what);
};

/// Move-only owner of one hid_t; closes it with the right H5*close.
class Handle {
  public:
    Handle() = default;
    explicit Handle(hid id)
        : id_(id) {}
    Handle(Handle&& o) noexcept
        : id_(o.id_) {
        o.id_ = -1;
    }
    Handle& operator=(Handle&& o) noexcept;
    Handle(const Handle&) = delete;
    Handle& operator=(const Handle&) = delete;
    ~Handle();
    hid get() const { return id_; }
    bool valid() const { return id_ >= 0; }
    /// Gives up ownership (the id is not closed by this Handle).
    hid release() {
        const hid i = id_;
        id_ = -1;
        return i;
    }

  private:
    hid id_ = -1;
};

enum class Mode { read, read_write, create_truncate };

/// Element types datasets and attributes may hold.
template <class T>
concept Element = std::same_as<T, double> || std::same_as<T, float> ||
    std::same_as<T, std::int32_t> || std::same_as<T, std::int64_t> ||
    std::same_as<T, std::uint8_t> || std::same_as<T, std::uint64_t>;

/// Open HDF5 file. Paths are absolute ("/nodes/volume"); parents are created on write.
/// Under MPI-IO every call is collective (every rank makes it, with the same arguments); the
/// whole-dataset writes take rank 0's data, the *_runs writes each rank's own rows.
class File {
  public:
    /// Opens or creates `name`. With `mpi_comm` != nullptr (an MPI_Comm*), uses the MPI-IO
    /// driver (collective open; every rank of the communicator must call).
    File(const std::string& name, Mode mode, const void* mpi_comm = nullptr);
    File(File&&) noexcept = default;
    File& operator=(File&&) noexcept = default;
    ~File() = default;

    const std::string& name() const { return name_; }
    /// True while the file's name still leads to the file opened (same device and inode): false
    /// once it was renamed, removed or replaced during the run.
    bool still_named() const;
    bool parallel() const { return parallel_; }
    /// Writes every buffer to disk; throws Error if HDF5 or the disk (ENOSPC, EIO) fails.
    void flush();
    /// Flushes and closes, checked (the destructor closes too but cannot report a failure, e.g.
    /// a full disk: call close() where the data matter). Collective under MPI-IO.
    void close();

    // ---- structure
    bool exists(const std::string& path) const; ///< link exists (every parent too)
    void create_group(const std::string& path); ///< with parents; no-op if it exists
    std::vector<std::string> list(const std::string& group) const; ///< child names, sorted
    void remove(const std::string& path);                          ///< unlink
    void hard_link(const std::string& target, const std::string& link);
    bool is_group(const std::string& path) const;

    // ---- datasets
    dims_t shape(const std::string& path) const;
    /// Class of the stored element: 'f' float, 'i' signed int, 'u' unsigned, 's' string.
    char type_class(const std::string& path) const;
    std::size_t type_size(const std::string& path) const;

    template <Element T>
    void write(const std::string& path, std::span<const T> data, const dims_t& dims);
    template <Element T>
    void write(const std::string& path, const std::vector<T>& data, const dims_t& dims) {
        write(path, std::span<const T>(data), dims);
    }
    template <Element T>
    void write(const std::string& path, const std::vector<T>& data) {
        write(path, std::span<const T>(data), dims_t{data.size()});
    }
    template <Element T>
    void write_scalar(const std::string& path, T value);
    void write_string(const std::string& path, const std::string& value);

    /// Reads a whole dataset, converting to T; `dims` receives the shape if not null.
    template <Element T>
    std::vector<T> read(const std::string& path, dims_t* dims = nullptr) const;
    template <Element T>
    T read_scalar(const std::string& path) const;
    std::string read_string(const std::string& path) const;
    /// Refuses (Error) dataset `path` whose declared size the file cannot hold (as a whole read
    /// does): for readers that scan a dataset in blocks of rows.
    void check_storage(const std::string& path) const;
    /// Reads rows [row0, row0+count) along axis 0.
    template <Element T>
    std::vector<T> read_rows(const std::string& path, std::uint64_t row0,
                             std::uint64_t count) const;

    /// Creates an empty dataset of shape (0, inner...) extendible along axis 0, chunked;
    /// `deflate` 1-9 compresses the chunks (gzip; under MPI-IO with collective writes).
    template <Element T>
    void create_extendible(const std::string& path, const dims_t& inner, std::uint64_t chunk_rows,
                           int deflate = 0);
    /// Appends `rows` rows (each the product of the inner dims) along axis 0.
    template <Element T>
    void append(const std::string& path, std::span<const T> data, std::uint64_t rows);
    /// Shrinks or grows axis 0 of an extendible dataset to `rows`.
    void resize_rows(const std::string& path, std::uint64_t rows);
    /// True unless `path` is a chunked dataset whose chunks are allocated late (on first write).
    /// MPI-IO cannot extend and write those (HDF5 1.10: pwritev EINVAL, then a damaged file):
    /// create_extendible allocates early; files written before pd-file 1.2.1 did not.
    bool allocated_early(const std::string& path) const;
    /// Rewrites the chunked dataset `path` (data, attributes, chunking, filters) with early
    /// allocation, in blocks of rows. Serial files only (not under MPI-IO).
    void reallocate_early(const std::string& path);
    /// Creates a dataset of shape `dims` (axis 0 indexes rows, e.g. nodes) and writes the rows
    /// of `runs` from `full`, which holds all rows (only those of `runs` are read).
    template <Element T>
    void write_runs(const std::string& path, std::span<const T> full, const dims_t& dims,
                    const runs_t& runs);
    /// Appends one entry along axis 0 of an extendible dataset (entries, rows, inner...) and
    /// writes the rows of `runs` of it from `full` (rows x inner values).
    template <Element T>
    void append_runs(const std::string& path, std::span<const T> full, const runs_t& runs);
    /// Overwrites rows [row0, row0+rows) of an existing dataset.
    template <Element T>
    void write_rows(const std::string& path, std::span<const T> data, std::uint64_t row0,
                    std::uint64_t rows);

    // ---- attributes (on a group or dataset at `path`)
    bool has_attr(const std::string& path, const std::string& name) const;
    template <Element T>
    void set_attr(const std::string& path, const std::string& name, T value);
    template <Element T>
    void set_attr(const std::string& path, const std::string& name, const std::vector<T>& v);
    void set_attr(const std::string& path, const std::string& name, const std::string& value);
    void set_attr(const std::string& path, const std::string& name, const char* value) {
        set_attr(path, name, std::string(value));
    }
    void set_attr(const std::string& path, const std::string& name,
                  const std::vector<std::string>& value);
    template <Element T>
    std::vector<T> attr_vector(const std::string& path, const std::string& name) const;
    template <Element T>
    T attr(const std::string& path, const std::string& name) const;
    std::string attr_string(const std::string& path, const std::string& name) const;
    /// A string array attribute (variable or fixed length).
    std::vector<std::string> attr_strings(const std::string& path, const std::string& name) const;
    std::vector<std::string> attr_names(const std::string& path) const;

  private:
    Handle open_object(const std::string& path) const;
    Handle open_dataset(const std::string& path) const;
    void ensure_parent(const std::string& path);
    /// Under MPI-IO, empties both selections on every rank but 0.
    void root_only(hid file_space, hid mem_space) const;
    [[noreturn]] void fail(const std::string& path, const std::string& what) const;
    /// Refuses (Error) a read of `elements` values of `bytes_each` from dataset `d` at `path`
    /// that the file cannot hold: above 64 MiB and more than 1100 x the bytes the dataset stores
    /// (gzip's best ratio is about 1030), e.g. a huge declared, never-written dataset. Checked
    /// before anything is allocated.
    void check_read_size(hid d, const std::string& path, double elements,
                         std::size_t bytes_each) const;
    /// The same for attribute `a` (`name`) of the object at `path`.
    void check_attr_size(hid a, const std::string& path, const std::string& name, double elements,
                         std::size_t bytes_each) const;

    std::string name_;
    std::uint64_t dev_ = 0, ino_ = 0; ///< the file opened (still_named)
    bool parallel_ = false;
    int rank_ = 0;
    FileLock lock_; ///< pdgrain's lock (writers; rank 0 under MPI); released after id_ closes
    Handle id_;
    Handle xfer_; ///< dataset transfer plist (collective under MPI-IO)
};

/// True if `name` is an HDF5 file (signature present); never throws.
bool is_hdf5(const std::string& name);

} // namespace pd::h5
