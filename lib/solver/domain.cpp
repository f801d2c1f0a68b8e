// SPDX-License-Identifier: MIT
#include "solver/domain.hpp"

#include "core/errors.hpp"

#include <algorithm>
#include <limits>
#include <numeric>

namespace pd::solver {

namespace {

template <class T>
MPI_Datatype mpi_type();
template <>
MPI_Datatype mpi_type<double>() {
    return MPI_DOUBLE;
}
template <>
MPI_Datatype mpi_type<std::uint8_t>() {
    return MPI_UINT8_T;
}
template <>
MPI_Datatype mpi_type<std::int32_t>() {
    return MPI_INT32_T;
}

int as_count(std::size_t n) {
    if (n > static_cast<std::size_t>(std::numeric_limits<int>::max()))
        throw InternalError(fmt::format("MPI message of {} values exceeds the int count limit", n));
    return static_cast<int>(n);
}

} // namespace

Domain::Domain(std::size_t n)
    : n_(n) {
    rows_.resize(n);
    std::iota(rows_.begin(), rows_.end(), index_t{0});
    if (n > 0)
        runs_.push_back({0, n});
    count_.assign(1, static_cast<int>(n));
}

Domain::Domain(MPI_Comm comm, std::vector<std::int32_t> owner)
    : comm_(comm)
    , n_(owner.size())
    , owner_(std::move(owner)) {
    MPI_Comm_rank(comm_, &rank_);
    MPI_Comm_size(comm_, &size_);
    count_.assign(static_cast<std::size_t>(size_), 0);
    for (auto o : owner_) {
        if (o < 0 || o >= size_)
            throw InternalError(fmt::format("node owner {} outside [0, {})", o, size_));
        ++count_[static_cast<std::size_t>(o)];
    }
    for (std::size_t i = 0; i < n_; ++i)
        if (owner_[i] == rank_) {
            rows_.push_back(static_cast<index_t>(i));
            if (!runs_.empty() && runs_.back()[1] == i)
                runs_.back()[1] = i + 1;
            else
                runs_.push_back({i, i + 1});
        }
    // Unpacking order of allgather: rank 0's rows, then rank 1's, ...
    std::vector<std::size_t> at(static_cast<std::size_t>(size_) + 1, 0);
    for (int p = 0; p < size_; ++p)
        at[static_cast<std::size_t>(p) + 1] =
            at[static_cast<std::size_t>(p)] +
            static_cast<std::size_t>(count_[static_cast<std::size_t>(p)]);
    order_.resize(n_);
    for (std::size_t i = 0; i < n_; ++i)
        order_[at[static_cast<std::size_t>(owner_[i])]++] = static_cast<index_t>(i);
}

void Domain::set_ghosts(const std::vector<index_t>& needed) {
    if (size_ == 1)
        return;
    std::vector<index_t> ghosts;
    for (auto j : needed)
        if (!owns(j))
            ghosts.push_back(j);
    std::sort(ghosts.begin(), ghosts.end());
    ghosts.erase(std::unique(ghosts.begin(), ghosts.end()), ghosts.end());
    num_ghosts_ = ghosts.size();
    const auto P = static_cast<std::size_t>(size_);
    std::vector<std::vector<index_t>> recv(P);
    for (auto j : ghosts)
        recv[static_cast<std::size_t>(owner(j))].push_back(j);
    std::vector<int> rc(P), sc(P);
    for (std::size_t p = 0; p < P; ++p)
        rc[p] = as_count(recv[p].size());
    MPI_Alltoall(rc.data(), 1, MPI_INT, sc.data(), 1, MPI_INT, comm_);
    std::vector<int> rd(P + 1, 0), sd(P + 1, 0);
    for (std::size_t p = 0; p < P; ++p) {
        rd[p + 1] = rd[p] + rc[p];
        sd[p + 1] = sd[p] + sc[p];
    }
    std::vector<index_t> want(static_cast<std::size_t>(rd[P])),
        give(static_cast<std::size_t>(sd[P]));
    for (std::size_t p = 0; p < P; ++p)
        std::copy(recv[p].begin(), recv[p].end(), want.begin() + rd[p]);
    static_assert(sizeof(index_t) == sizeof(std::int32_t));
    MPI_Alltoallv(want.data(), rc.data(), rd.data(), MPI_INT32_T, give.data(), sc.data(), sd.data(),
                  MPI_INT32_T, comm_);
    peers_.clear();
    for (std::size_t p = 0; p < P; ++p) {
        if (rc[p] == 0 && sc[p] == 0)
            continue;
        Peer q{static_cast<int>(p),
               {give.begin() + sd[p], give.begin() + sd[p + 1]},
               std::move(recv[p])};
        for (auto i : q.send)
            if (!owns(i))
                throw InternalError(
                    fmt::format("rank {} asked rank {} for node {} it does not own", p, rank_, i));
        peers_.push_back(std::move(q));
    }
}

void Domain::exchange(std::initializer_list<std::vector<double>*> fields, int ncomp) {
    if (size_ == 1 || peers_.empty())
        return;
    const std::size_t per = fields.size() * static_cast<std::size_t>(ncomp);
    std::size_t ns = 0, nr = 0;
    for (const auto& q : peers_) {
        ns += q.send.size();
        nr += q.recv.size();
    }
    sendbuf_.resize(ns * per);
    recvbuf_.resize(nr * per);
    std::vector<MPI_Request> req;
    req.reserve(2 * peers_.size());
    std::size_t at = 0;
    for (const auto& q : peers_) {
        const std::size_t len = q.recv.size() * per;
        if (len > 0) {
            req.emplace_back();
            MPI_Irecv(recvbuf_.data() + at, as_count(len), MPI_DOUBLE, q.rank, 71, comm_,
                      &req.back());
        }
        at += len;
    }
    at = 0;
    for (const auto& q : peers_) {
        double* b = sendbuf_.data() + at;
        for (auto i : q.send)
            for (auto* fld : fields)
                for (int c = 0; c < ncomp; ++c)
                    *b++ = (*fld)[static_cast<std::size_t>(ncomp * i + c)];
        const std::size_t len = q.send.size() * per;
        if (len > 0) {
            req.emplace_back();
            MPI_Isend(sendbuf_.data() + at, as_count(len), MPI_DOUBLE, q.rank, 71, comm_,
                      &req.back());
        }
        at += len;
    }
    MPI_Waitall(static_cast<int>(req.size()), req.data(), MPI_STATUSES_IGNORE);
    ++traffic_.exchanges;
    for (const auto& q : peers_) {
        traffic_.messages_sent += q.send.empty() ? 0 : 1;
        traffic_.messages_recv += q.recv.empty() ? 0 : 1;
    }
    traffic_.bytes_sent += static_cast<std::int64_t>(ns * per * sizeof(double));
    traffic_.bytes_recv += static_cast<std::int64_t>(nr * per * sizeof(double));
    const double* b = recvbuf_.data();
    for (const auto& q : peers_)
        for (auto j : q.recv)
            for (auto* fld : fields)
                for (int c = 0; c < ncomp; ++c)
                    (*fld)[static_cast<std::size_t>(ncomp * j + c)] = *b++;
}

template <class T>
void Domain::gather_rows(std::vector<T>& a, const std::vector<offset_t>* offsets, int ncomp) const {
    if (size_ == 1)
        return;
    auto lo = [&](index_t i) {
        return offsets ? static_cast<std::size_t>((*offsets)[static_cast<std::size_t>(i)])
                       : static_cast<std::size_t>(ncomp) * static_cast<std::size_t>(i);
    };
    auto hi = [&](index_t i) { return lo(i + 1); };
    std::vector<T> mine;
    for (auto i : rows_)
        mine.insert(mine.end(), a.begin() + static_cast<std::ptrdiff_t>(lo(i)),
                    a.begin() + static_cast<std::ptrdiff_t>(hi(i)));
    const auto P = static_cast<std::size_t>(size_);
    std::vector<int> cnt(P), disp(P + 1, 0);
    std::size_t k = 0;
    for (std::size_t p = 0; p < P; ++p) {
        std::size_t len = 0;
        for (int q = 0; q < count_[p]; ++q, ++k)
            len += hi(order_[k]) - lo(order_[k]);
        cnt[p] = as_count(len);
        disp[p + 1] = disp[p] + cnt[p];
    }
    std::vector<T> all(static_cast<std::size_t>(disp[P]));
    MPI_Allgatherv(mine.data(), as_count(mine.size()), mpi_type<T>(), all.data(), cnt.data(),
                   disp.data(), mpi_type<T>(), comm_);
    ++traffic_.gathers;
    traffic_.gather_bytes += static_cast<std::int64_t>((all.size() - mine.size()) * sizeof(T));
    const T* b = all.data();
    for (auto i : order_) {
        const auto l = lo(i), h = hi(i);
        std::copy(b, b + (h - l), a.begin() + static_cast<std::ptrdiff_t>(l));
        b += h - l;
    }
}

void Domain::allgather(std::vector<double>& a, int ncomp) const {
    gather_rows(a, nullptr, ncomp);
}

void Domain::allgather(std::vector<std::uint8_t>& a, int ncomp) const {
    gather_rows(a, nullptr, ncomp);
}

void Domain::allgather_csr(std::vector<std::uint8_t>& a,
                           const std::vector<offset_t>& offsets) const {
    gather_rows(a, &offsets, 1);
}

void Domain::allgather_csr(std::vector<index_t>& a, const std::vector<offset_t>& offsets) const {
    gather_rows(a, &offsets, 1);
}

double Domain::sum(double v) const {
    if (size_ == 1)
        return v;
    double r = 0;
    ++traffic_.reductions;
    MPI_Allreduce(&v, &r, 1, MPI_DOUBLE, MPI_SUM, comm_);
    return r;
}

std::int64_t Domain::sum(std::int64_t v) const {
    if (size_ == 1)
        return v;
    std::int64_t r = 0;
    ++traffic_.reductions;
    MPI_Allreduce(&v, &r, 1, MPI_INT64_T, MPI_SUM, comm_);
    return r;
}

void Domain::sum(std::vector<double>& v) const {
    if (size_ > 1 && !v.empty()) {
        ++traffic_.reductions;
        MPI_Allreduce(MPI_IN_PLACE, v.data(), as_count(v.size()), MPI_DOUBLE, MPI_SUM, comm_);
    }
}

double Domain::max(double v) const {
    if (size_ == 1)
        return v;
    double r = 0;
    ++traffic_.reductions;
    MPI_Allreduce(&v, &r, 1, MPI_DOUBLE, MPI_MAX, comm_);
    return r;
}

double Domain::min(double v) const {
    return -max(-v);
}

bool Domain::any(bool v) const {
    if (size_ == 1)
        return v;
    int a = v ? 1 : 0, r = 0;
    ++traffic_.reductions;
    MPI_Allreduce(&a, &r, 1, MPI_INT, MPI_MAX, comm_);
    return r != 0;
}

void Domain::min(std::vector<index_t>& v) const {
    static_assert(sizeof(index_t) == 4, "MPI_INT32_T below");
    if (size_ > 1 && !v.empty()) {
        ++traffic_.reductions;
        MPI_Allreduce(MPI_IN_PLACE, v.data(), as_count(v.size()), MPI_INT32_T, MPI_MIN, comm_);
    }
}

void Domain::max(std::vector<std::uint8_t>& v) const {
    if (size_ > 1 && !v.empty()) {
        ++traffic_.reductions;
        MPI_Allreduce(MPI_IN_PLACE, v.data(), as_count(v.size()), MPI_UINT8_T, MPI_MAX, comm_);
    }
}

} // namespace pd::solver
