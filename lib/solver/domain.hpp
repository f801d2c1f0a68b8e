// SPDX-License-Identifier: MIT
// Domain decomposition of the nodes over MPI ranks (STYLE 2.2 "parallel layering").
//
// Every rank holds the model (reference configuration, bonds, conditions: read-only) and the
// state arrays at full length, but integrates and computes forces only for the nodes it owns
// (`rows()`, ascending global ids). The state of a node another rank owns is valid on this rank
// only where it is a ghost: a bond neighbour of an owned node, or a contact candidate of one.
// Ghost values (x, u, v; LPS dilatation) come from their owners each step in neighbour-only
// point-to-point messages. Contact-list rebuilds (rare, decided collectively) gather every
// owned position once, rebuild, and set the ghost set anew, so the ghosts follow the grains.
//
// Every force sum runs over the same neighbours in the same order as on one rank (bond rows in
// CSR order, contact rows sorted by global id), so the state is bitwise the same at any rank
// count; only observables (sums over ranks) differ in the last bits.
#pragma once

#include "solver/state.hpp"

#include <mpi.h>

#include <array>
#include <cstdint>
#include <initializer_list>
#include <vector>

namespace pd::solver {

/// [begin, end) along the node axis.
using Runs = std::vector<std::array<std::uint64_t, 2>>;

/// What this rank's messages carried since the Domain was built (issue 29 item 6): the
/// neighbour-only ghost exchanges (point-to-point, counted per peer message) and the
/// whole-array gathers (contact-list rebuilds, fragments; bytes this rank received). A few
/// integer adds per call: nothing measurable against the messages themselves.
struct Traffic {
    std::int64_t exchanges = 0;     ///< exchange() calls
    std::int64_t messages_sent = 0; ///< point-to-point sends of exchange()
    std::int64_t messages_recv = 0;
    std::int64_t bytes_sent = 0;
    std::int64_t bytes_recv = 0;
    std::int64_t gathers = 0;      ///< allgather calls (every rank gets every owner's rows)
    std::int64_t gather_bytes = 0; ///< bytes received by them (the other ranks' rows)
    std::int64_t reductions = 0;   ///< all-reduce calls (sum, max, min, any)
};

class Domain {
  public:
    /// One rank owns all `n` nodes (serial runs, unit tests). No MPI call is made.
    explicit Domain(std::size_t n);
    /// `owner[i]` = rank owning node i (in [0, size)). Collective over `comm`.
    Domain(MPI_Comm comm, std::vector<std::int32_t> owner);

    int rank() const { return rank_; }
    int size() const { return size_; }
    bool distributed() const { return size_ > 1; }
    MPI_Comm comm() const { return comm_; }
    std::size_t num_nodes() const { return n_; }

    /// Owned nodes, ascending global ids.
    const std::vector<index_t>& rows() const { return rows_; }
    /// Owned nodes as runs of consecutive ids (hyperslab selections of frames and checkpoints).
    const Runs& runs() const { return runs_; }
    bool owns(index_t i) const {
        return size_ == 1 || owner_[static_cast<std::size_t>(i)] == rank_;
    }
    /// Owner of every node (empty on one rank).
    const std::vector<std::int32_t>& owner_map() const { return owner_; }
    std::int32_t owner(index_t i) const {
        return size_ == 1 ? 0 : owner_[static_cast<std::size_t>(i)];
    }

    /// Collective: the ghosts are the non-owned nodes among `needed` (any order, duplicates
    /// allowed). Owners learn what to send (one all-to-all of counts, one of ids).
    void set_ghosts(const std::vector<index_t>& needed);
    std::size_t num_ghosts() const { return num_ghosts_; }
    /// Number of ranks this rank exchanges ghosts with.
    std::size_t num_neighbours() const { return peers_.size(); }
    /// Messages and bytes since construction (differences of two snapshots give a run's).
    const Traffic& traffic() const { return traffic_; }
    /// Starts from another domain's counts (a re-partition hands the run over to a new one).
    void continue_traffic(const Traffic& t) { traffic_ = t; }

    /// Calls f(i) for every ghost node i (after set_ghosts).
    template <class F>
    void for_each_ghost(F&& f) const {
        for (const auto& p : peers_)
            for (const auto i : p.recv)
                f(i);
    }
    /// Neighbour-only: every ghost gets its owner's values of each field (`ncomp` per node).
    void exchange(std::initializer_list<std::vector<double>*> fields, int ncomp);
    /// Every rank gets every node's values from its owner (`ncomp` per node).
    void allgather(std::vector<double>& a, int ncomp) const;
    void allgather(std::vector<std::uint8_t>& a, int ncomp) const;
    /// Same for CSR data: rows of node i span [offsets[i], offsets[i+1]) (bond state).
    void allgather_csr(std::vector<std::uint8_t>& a, const std::vector<offset_t>& offsets) const;
    void allgather_csr(std::vector<index_t>& a, const std::vector<offset_t>& offsets) const;

    double sum(double v) const;
    std::int64_t sum(std::int64_t v) const;
    void sum(std::vector<double>& v) const; ///< in place, element-wise
    double max(double v) const;
    double min(double v) const;
    bool any(bool v) const;
    void max(std::vector<std::uint8_t>& v) const; ///< in place, element-wise
    void min(std::vector<index_t>& v) const;      ///< in place, element-wise

  private:
    template <class T>
    void gather_rows(std::vector<T>& a, const std::vector<offset_t>* offsets, int ncomp) const;

    MPI_Comm comm_ = MPI_COMM_SELF;
    int rank_ = 0;
    int size_ = 1;
    std::size_t n_ = 0;
    std::vector<std::int32_t> owner_;
    std::vector<index_t> rows_;
    Runs runs_;
    std::vector<index_t> order_; ///< every rank's rows, rank by rank (allgather unpacking)
    std::vector<int> count_;     ///< owned nodes per rank
    struct Peer {
        int rank;
        std::vector<index_t> send; ///< owned nodes this peer keeps as ghosts
        std::vector<index_t> recv; ///< ghosts this peer owns
    };
    std::vector<Peer> peers_;
    std::size_t num_ghosts_ = 0;
    std::vector<double> sendbuf_, recvbuf_;
    mutable Traffic traffic_; ///< gathers are const
};

} // namespace pd::solver
