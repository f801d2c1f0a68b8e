// SPDX-License-Identifier: MIT
#include "pipeline/rank_report.hpp"

#include "core/timer.hpp"
#include "pipeline/run/schedule.hpp"
#include "solver/solver.hpp"

#include <algorithm>
#include <array>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace pd::pipeline {

namespace {

/// The solver's halo timer exists under MPI only (looked up here, it would appear at one rank).
double halo_seconds(solver::Solver& s) {
    Timers& t = s.timers();
    return s.domain().distributed() ? t.total(t.id("pd::solver::halo_exchange")) : 0.0;
}

// One rank's row of the report; the order of `fields` below.
enum Col {
    c_owned,
    c_ghosts,
    c_bond,
    c_contact,
    c_peers,
    c_msgs,
    c_sent,
    c_recv,
    c_gathered,
    c_reductions,
    c_loop,
    c_busy,
    c_halo,
    c_rss,
    c_num
};

std::array<double, c_num> row_of(solver::Solver& s, const RankMark& from, double per) {
    const auto& d = s.domain();
    const auto now = mark_rank(s);
    const auto& a = now.traffic;
    const auto& b = from.traffic;
    std::array<double, c_num> r{};
    r[c_owned] = static_cast<double>(d.rows().size());
    r[c_ghosts] = static_cast<double>(d.num_ghosts());
    r[c_bond] = static_cast<double>(s.bond_ghosts());
    r[c_contact] = static_cast<double>(s.contact_ghosts());
    r[c_peers] = static_cast<double>(d.num_neighbours());
    r[c_msgs] = per * static_cast<double>(a.messages_sent - b.messages_sent);
    r[c_sent] = per * static_cast<double>(a.bytes_sent - b.bytes_sent);
    r[c_recv] = per * static_cast<double>(a.bytes_recv - b.bytes_recv);
    r[c_gathered] = static_cast<double>(a.gather_bytes - b.gather_bytes);
    r[c_reductions] = per * static_cast<double>(a.reductions - b.reductions);
    r[c_loop] = now.wall - from.wall;
    r[c_busy] = now.busy - from.busy;
    r[c_halo] = now.halo - from.halo;
    r[c_rss] = peak_rss_bytes();
    return r;
}

} // namespace

double peak_rss_bytes() {
    std::ifstream in("/proc/self/status");
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream ss(line);
        std::string key;
        double kb = 0;
        if (ss >> key >> kb && key == "VmHWM:")
            return kb * 1024;
    }
    return 0;
}

RankMark mark_rank(solver::Solver& s) {
    return {s.domain().traffic(), wall_seconds(), run::busy_seconds(s.timers()), halo_seconds(s)};
}

void report_ranks(Context& ctx, solver::Solver& s, const RankMark& from, std::int64_t steps) {
    const double per = steps > 0 ? 1.0 / static_cast<double>(steps) : 0.0;
    const auto& d = s.domain();
    const auto P = static_cast<std::size_t>(ctx.size);
    std::vector<double> all(P * c_num, 0.0); // every rank its slot, summed: a gather
    const auto mine = row_of(s, from, per);
    std::copy(mine.begin(), mine.end(),
              all.begin() + static_cast<std::ptrdiff_t>(c_num * ctx.rank));
    d.sum(all);
    auto stat = [&](Col c, bool max) { // max, or mean, over ranks
        double m = 0;
        for (std::size_t p = 0; p < P; ++p)
            m = max ? std::max(m, all[p * c_num + c])
                    : m + all[p * c_num + c] / static_cast<double>(P);
        return m;
    };
    if (P > 1)
        ctx.log.info("halo over {} steps, max/mean of {} ranks: ghosts {:.0f}/{:.0f} (bond "
                     "{:.0f}/{:.0f}, contact {:.0f}/{:.0f}), peers {:.0f}/{:.1f}, sent "
                     "{:.4g}/{:.4g} B/step in {:.1f}/{:.1f} messages, gathered {:.4g}/{:.4g} B, "
                     "halo {:.3g}/{:.3g} s of {:.3g} s, peak RSS {:.1f}/{:.1f} MB",
                     steps, P, stat(c_ghosts, true), stat(c_ghosts, false), stat(c_bond, true),
                     stat(c_bond, false), stat(c_contact, true), stat(c_contact, false),
                     stat(c_peers, true), stat(c_peers, false), stat(c_sent, true),
                     stat(c_sent, false), stat(c_msgs, true), stat(c_msgs, false),
                     stat(c_gathered, true), stat(c_gathered, false), stat(c_halo, true),
                     stat(c_halo, false), stat(c_loop, true), stat(c_rss, true) / 1e6,
                     stat(c_rss, false) / 1e6);
    for (std::size_t p = 0; p < P; ++p) {
        const double* r = all.data() + p * c_num;
        ctx.log.debug(
            "rank {}: owned {:.0f} ghosts {:.0f} bond {:.0f} contact {:.0f} peers {:.0f} "
            "msgs/step {:.6g} sent B/step {:.6g} recv B/step {:.6g} gathered B {:.6g} "
            "reductions/step {:.6g} loop s {:.6g} busy s {:.6g} halo s {:.6g} peak_rss B {:.0f}",
            p, r[c_owned], r[c_ghosts], r[c_bond], r[c_contact], r[c_peers], r[c_msgs], r[c_sent],
            r[c_recv], r[c_gathered], r[c_reductions], r[c_loop], r[c_busy], r[c_halo], r[c_rss]);
    }
}

} // namespace pd::pipeline
