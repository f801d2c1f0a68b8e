// SPDX-License-Identifier: MIT
// Time-dependent data in H5MD 1.1 form:
//   /particles/nodes/<field>/{step, time, value}   value (frames, nodes, 3) or (frames, nodes)
//   /observables/<name>/{step, time, value}         value (rows) or (rows, 3)
// step/time of every field are hard links to those of `position` (of `kinetic_energy` for
// observables). 2D runs store z = 0.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace pd::h5 {
class File;
}

namespace pd::store {

/// A nodal field stored in frames.
struct FieldInfo {
    std::string name; ///< "position", "velocity", "displacement", "force", "damage"
    int components;   ///< 3 or 1
    std::string unit; ///< SI unit string
};

/// The nodal fields pd-solve can write, in this order.
const std::vector<FieldInfo>& frame_fields();

/// Appends frames to /particles/nodes. Creates the groups on first use.
class FrameWriter {
  public:
    /// `fields` are names from frame_fields(); position is always written.
    /// `deflate` 1-9: gzip-compressed frames (0: none).
    FrameWriter(h5::File& f, std::size_t num_nodes, std::vector<std::string> fields,
                int deflate = 0);
    /// Under MPI: this rank writes only these nodes of each frame (their values in `data` at
    /// their own places); empty = all nodes.
    void set_runs(std::vector<std::array<std::uint64_t, 2>> runs) { runs_ = std::move(runs); }
    /// Appends one frame; `data` maps each field name to num_nodes * components values.
    void write(std::int64_t step, double time,
               const std::map<std::string, std::span<const double>>& data);
    std::size_t frames() const { return frames_; }
    const std::vector<std::string>& fields() const { return fields_; }
    /// Bytes one more frame can add to the file at most (every field's chunk, allocated whole,
    /// and a new chunk of step and time), metadata aside.
    std::uint64_t frame_bytes() const;
    /// Flags the last frame written as the state at a failing step (a guard's exit 3): the
    /// attributes failed_step (the step) and failure (what failed, e.g. "interpenetration") of
    /// /particles/nodes. Collective under MPI-IO (every rank the same values).
    void flag_failed(std::int64_t step, const std::string& failure);

  private:
    h5::File& f_;
    std::size_t n_;
    std::vector<std::string> fields_;
    std::size_t frames_ = 0;
    std::vector<std::array<std::uint64_t, 2>> runs_;
};

/// Reads frames one at a time (memory does not grow with the number of frames).
class FrameReader {
  public:
    explicit FrameReader(const h5::File& f);
    std::size_t num_frames() const { return steps_.size(); }
    std::size_t num_nodes() const { return n_; }
    std::vector<std::string> fields() const; ///< present fields
    int components(const std::string& field) const;
    std::string unit(const std::string& field) const;
    std::int64_t step(std::size_t k) const { return steps_[k]; }
    double time(std::size_t k) const { return times_[k]; }
    /// Values of `field` at frame k: num_nodes * components.
    std::vector<double> read(const std::string& field, std::size_t k) const;

  private:
    const h5::File& f_;
    std::size_t n_ = 0;
    std::vector<std::int64_t> steps_;
    std::vector<double> times_;
};

/// One observable series as read back.
struct Series {
    std::string unit;
    int components = 1;
    std::vector<std::int64_t> step;
    std::vector<double> time;
    std::vector<double> value; ///< rows * components
};

/// Observables that pd-solve writes: name -> (components, unit).
struct ObservableInfo {
    std::string name;
    int components;
    std::string unit;
    bool required = true; ///< false: added in a later pd-file minor version (older files lack it)
};
const std::vector<ObservableInfo>& observable_list();

/// Buffers observable rows in memory and appends them to /observables on flush(). With walls,
/// also `wall_force` and `wall_moment`, value (rows, num_walls, 3) in N and N m. With
/// `bodies` (the fixed or driven meshed bodies), also `body_force` and `body_moment`, value
/// (rows, bodies, 3) in N and N m, and `body_force/body` (the body ids, linked as
/// `body_moment/body`).
class ObservableWriter {
  public:
    explicit ObservableWriter(h5::File& f, std::size_t num_walls = 0,
                              std::vector<std::int32_t> bodies = {});
    /// Adds one row; `values` holds, for each entry of observable_list() in order, its
    /// components, then 3 * num_walls wall forces, then 3 * num_walls wall moments, then
    /// 3 * bodies.size() body forces, then as many body moments.
    void add(std::int64_t step, double time, std::span<const double> values);
    void flush();
    std::size_t buffered() const { return steps_.size(); }
    /// Bytes the next flush() can add to the file at most (the buffered rows, and a new chunk of
    /// every series), metadata aside; 0 with nothing buffered.
    std::uint64_t flush_bytes() const;

  private:
    h5::File& f_;
    std::size_t walls_;
    std::vector<std::int32_t> bodies_;
    std::vector<std::int64_t> steps_;
    std::vector<double> times_;
    std::vector<double> values_;
};

/// All series under /observables.
std::map<std::string, Series> read_observables(const h5::File& f);

/// The bodies of the `body_force` and `body_moment` series (their order), or empty when the file
/// has none (no fixed or driven body, or written before pd-file 1.2.0).
std::vector<std::int32_t> read_reaction_bodies(const h5::File& f);

/// Writes the time-independent H5MD elements species (= body id) and mass (kg) of each node.
void write_particle_constants(h5::File& f, const std::vector<std::int32_t>& species,
                              const std::vector<double>& mass);

/// Removes frames and observable rows with step > `step` (restart from a checkpoint); first
/// makes the series appendable under MPI-IO (allocate_for_parallel_append). Serial file only.
void truncate_after(h5::File& f, std::int64_t step);

/// Rewrites the frame and observable series that a serial run of pd-file < 1.2.1 created with
/// late chunk allocation, which MPI-IO cannot extend (issue 13); no-op on newer files.
void allocate_for_parallel_append(h5::File& f);

} // namespace pd::store
