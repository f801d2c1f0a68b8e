// SPDX-License-Identifier: MIT
// /checkpoints/step_<N>: everything a restart needs to continue bit for bit (spec decision 5):
// step, time, dt, displacement, velocity, force density, bond state, broken-bond count. A
// checkpoint is written completely and flushed before /checkpoints@latest names it; the
// previous one is deleted only after that, so a crash mid-write leaves the previous one valid.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace pd::h5 {
class File;
}

namespace pd::store {

struct Checkpoint {
    std::int64_t step = 0;
    double time = 0;                 ///< s
    double dt = 0;                   ///< s
    std::vector<double> u, v, f;     ///< 3 per node: m, m s-1, N m-3 (force density)
    std::vector<std::uint8_t> alive; ///< per bond (full CSR list)
    std::int64_t broken_total = 0;   ///< broken bonds counted from both ends
    double external_work = 0;        ///< J, since t = 0
    double external_power = 0;       ///< W, at this step (trapezoidal work integration)
    /// Energy dissipated since t = 0 (J: fracture, damping, friction, viscous) and the rates of
    /// the last force evaluation (W: damping, friction, viscous), in checkpoint_dissipation
    /// order. Files before pd-file 1.2 have none: zeros.
    std::array<double, 7> dissipation{};
    /// The wall and body reactions summed over the steps of the open observation interval
    /// (solver::Solver::interval_sum, summed over the ranks) and their count (pd-file 1.3;
    /// absent before: an empty sum over 0 steps).
    std::vector<double> interval_sum;
    std::int64_t interval_steps = 0;
    /// Under MPI, what this rank writes: its nodes' rows of u, v, f and its bonds' entries of
    /// `alive` ([begin, end) runs; the vectors hold every node and bond). Empty = all.
    std::vector<std::array<std::uint64_t, 2>> node_runs, bond_runs;
    /// The surface law's depth history (solver::ContactList::depth_history): (node, body)
    /// pairs, 2 per entry, and depths (m) of every rank's entries, at depth_time (s; < 0: none,
    /// and no datasets). Written: this rank's rows `depth_runs` of the vectors (all entries).
    std::vector<std::int64_t> depth_pairs;
    std::vector<double> depths;
    double depth_time = -1;
    std::vector<std::array<std::uint64_t, 2>> depth_runs;
    /// The surface law's last contact-list rebuild: every node's position then (3 per node, m)
    /// and whether it kept half its bonds then (1 per node); empty: none. Written by node_runs.
    std::vector<double> build_x;
    std::vector<std::uint8_t> build_whole;
};

/// Attribute names of Checkpoint::dissipation.
const std::array<const char*, 7>& checkpoint_dissipation();

/// Writes `c` as /checkpoints/step_<N>, then points @latest at it and deletes older ones.
void write_checkpoint(h5::File& f, const Checkpoint& c);

/// The latest complete checkpoint, checked against `num_nodes` and `num_bonds`; nullopt if none.
std::optional<Checkpoint> read_latest_checkpoint(const h5::File& f, std::size_t num_nodes,
                                                 std::size_t num_bonds);

} // namespace pd::store
