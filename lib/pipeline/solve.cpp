// SPDX-License-Identifier: MIT
#include "pipeline/solve.hpp"

#include "core/errors.hpp"
#include "core/file_lock.hpp"
#include "core/timer.hpp"
#include "h5/file.hpp"
#include "partition/graph.hpp"
#include "pipeline/partition.hpp"
#include "solver/solver.hpp"
#include "store/checkpoint_io.hpp"
#include "store/frames.hpp"
#include "store/model_io.hpp"
#include "store/provenance.hpp"
#include "store/schema.hpp"

#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <unistd.h>

namespace pd::pipeline {

namespace {

/// Pre-emption: SIGTERM or SIGUSR1 (Slurm before the wall-time limit, or on pre-emption) asks the
/// run to stop. The step loop finishes the current step, writes a checkpoint and exits with
/// exit_preempted (75); under MPI the ranks agree on the step by an Allreduce of the flag.
volatile std::sig_atomic_t stop_signal = 0;

extern "C" void on_stop_signal(int sig) {
    stop_signal = sig;
}

/// Installs the handlers for the life of a solve; the previous ones come back after it.
class StopSignals {
  public:
    StopSignals() {
        stop_signal = 0;
        struct sigaction sa {};
        sa.sa_handler = on_stop_signal;
        sigemptyset(&sa.sa_mask);
        sa.sa_flags = SA_RESTART;
        sigaction(SIGTERM, &sa, &old_term_);
        sigaction(SIGUSR1, &sa, &old_usr1_);
    }
    ~StopSignals() {
        sigaction(SIGTERM, &old_term_, nullptr);
        sigaction(SIGUSR1, &old_usr1_, nullptr);
    }
    StopSignals(const StopSignals&) = delete;
    StopSignals& operator=(const StopSignals&) = delete;

  private:
    struct sigaction old_term_ {};
    struct sigaction old_usr1_ {};
};

/// Steps between the ranks' agreement on a stop request under MPI (one Allreduce of an int).
constexpr std::int64_t stop_check_every = 10;

void write_frame(store::FrameWriter& fw, const solver::Solver& s, std::vector<double>& damage,
                 std::vector<double>& force) {
    thread_local std::vector<double> damage_z, fragment, broken;
    // Only the requested fields are computed.
    const auto& st = s.state();
    std::map<std::string, std::span<const double>> data;
    data["position"] = st.x;
    for (const auto& name : fw.fields()) {
        if (name == "velocity")
            data[name] = st.v;
        else if (name == "displacement")
            data[name] = st.u;
        else if (name == "force") {
            s.nodal_force(force);
            data[name] = force;
        } else if (name == "damage") {
            s.damage(damage);
            data[name] = damage;
        } else if (name == "broken_bonds") {
            s.broken_per_node(broken);
            data[name] = broken;
        } else if (name == "fragment") {
            s.fragments(fragment);
            data[name] = fragment;
        } else if (name == "damage_z") {
            s.damage_z(damage_z);
            data[name] = damage_z;
        }
    }
    fw.write(st.step, st.time, data);
}

/// Seconds a rank spent computing (forces, contact, integration; not the ghost exchange).
double busy_seconds(Timers& timers) {
    double busy = 0;
    for (const char* name :
         {"pd::solver::bond_forces", "pd::solver::contact_forces", "pd::solver::contact_search",
          "pd::solver::wall_contact", "pd::solver::integrate", "pd::solver::damping_friction"})
        busy += timers.total(timers.id(name));
    return busy;
}

std::vector<double> observable_row(const solver::Observables& o) {
    std::vector<double> r{o.kinetic_energy,
                          o.elastic_energy,
                          o.contact_energy,
                          o.external_work,
                          o.momentum[0],
                          o.momentum[1],
                          o.momentum[2],
                          static_cast<double>(o.contact_count),
                          static_cast<double>(o.broken_bonds),
                          o.fracture_energy,
                          o.damping_dissipation,
                          o.friction_dissipation,
                          o.viscous_dissipation,
                          o.gravity_potential};
    r.insert(r.end(), o.wall_force.begin(), o.wall_force.end());
    r.insert(r.end(), o.wall_moment.begin(), o.wall_moment.end());
    r.insert(r.end(), o.body_force.begin(), o.body_force.end());
    r.insert(r.end(), o.body_moment.begin(), o.body_moment.end());
    return r;
}

/// Re-partitions the grains where they are now (--rebalance, at a checkpoint): METIS on the
/// current grain graph; adopted if it cuts fewer near-grain pairs than the partition in use.
/// Collective. Returns the new domain (already handed to the solver), or nullptr.
std::unique_ptr<solver::Domain> rebalance(const model::Model& m, solver::Solver& s,
                                          const std::vector<std::int32_t>& owner, Context& ctx,
                                          const std::string& file) {
    const double t0 = wall_seconds();
    MPI_Comm comm = s.domain().comm();
    const auto centre = s.body_centres();
    const std::size_t nb = m.bodies.num();
    std::vector<std::int32_t> next(m.nodes.num());
    std::int64_t cut[2] = {0, 0};
    if (ctx.rank == 0) {
        std::vector<std::int32_t> now(nb);
        bool whole = true;
        for (std::size_t b = 0; b < nb; ++b) {
            now[b] = owner[static_cast<std::size_t>(m.bodies.begin(b))];
            for (auto i = m.bodies.begin(b); i < m.bodies.end(b); ++i)
                whole = whole && owner[static_cast<std::size_t>(i)] == now[b];
        }
        if (whole && nb >= 4 * static_cast<std::size_t>(ctx.size)) {
            const auto p = make_partition(m, ctx.size, "body", file, centre);
            double reach = 0;
            for (const auto& c : m.contact)
                reach = std::max(reach, 2 * c.radius);
            cut[0] = partition::edge_cut(partition::body_graph(m, reach, centre), now);
            cut[1] = p.edge_cut;
            next = node_owner(m, p);
        }
    }
    MPI_Bcast(cut, 2, MPI_INT64_T, 0, comm);
    if (!(cut[1] < cut[0])) {
        ctx.log.info("rebalance at step {}: kept the partition (edge cut {}, a new one {}; "
                     "{:.3g} s)",
                     s.state().step, cut[0], cut[1], wall_seconds() - t0);
        return nullptr;
    }
    MPI_Bcast(next.data(), static_cast<int>(next.size()), MPI_INT32_T, 0, comm);
    auto dom = std::make_unique<solver::Domain>(comm, std::move(next));
    s.redistribute(dom.get());
    ctx.log.info("rebalance at step {}: re-partitioned the grains where they are (edge cut: "
                 "near node pairs across ranks {} -> {}) in {:.3g} s",
                 s.state().step, cut[0], cut[1], wall_seconds() - t0);
    return dom;
}

/// Command-line values: finite, in range (CLI11 only parses them).
void check_options(const SolveOptions& opt) {
    if (opt.max_steps_given && opt.max_steps < 1)
        throw InputError(fmt::format("--steps {}: must be at least 1", opt.max_steps));
    if (opt.final_time_given && !(std::isfinite(opt.final_time) && opt.final_time > 0))
        throw InputError(
            fmt::format("--final-time {}: must be a finite time > 0 (s)", opt.final_time));
    if (!(std::isfinite(opt.energy_tolerance) && opt.energy_tolerance >= 0))
        throw InputError(fmt::format("--energy-tolerance {}: must be a finite fraction >= 0",
                                     opt.energy_tolerance));
    if (!(opt.checkpoint_wall_seconds >= 0))
        throw InputError(fmt::format("--checkpoint-every-wall {}: must be >= 0 (s)",
                                     opt.checkpoint_wall_seconds));
    if (!(opt.progress_seconds >= 0))
        throw InputError(
            fmt::format("--progress-every {}: must be >= 0 (s)", opt.progress_seconds));
    if (opt.compress < 0 || opt.compress > 9)
        throw InputError(fmt::format("--compress {}: must be 0-9", opt.compress));
}

/// A fresh run deletes the frames, observables and checkpoints of a file: only with --overwrite.
void refuse_existing_results(const h5::File& rf, const std::string& file) {
    std::string what;
    if (rf.exists(std::string(store::path::particles) + "/position/value")) {
        const store::FrameReader fr(rf);
        what = fmt::format("{} frame{}", fr.num_frames(), fr.num_frames() == 1 ? "" : "s");
        if (fr.num_frames() > 0)
            what += fmt::format(" (up to step {}, t = {:.6g} s)", fr.step(fr.num_frames() - 1),
                                fr.time(fr.num_frames() - 1));
    }
    if (rf.exists(store::path::checkpoints) && !rf.list(store::path::checkpoints).empty())
        what += (what.empty() ? "" : " and ") + std::string("a checkpoint");
    else if (rf.exists(store::path::observables) && what.empty())
        what = "observables";
    if (what.empty())
        return;
    throw InputError(fmt::format("{}: already holds the results of a run: {}. Continue it with "
                                 "--restart (add --final-time T to go further), or pass "
                                 "--overwrite to delete them and start again from t = 0",
                                 file, what));
}

} // namespace

void solve(const SolveOptions& opt, Context& ctx) {
    const double wall0 = wall_seconds();
    const StopSignals stop_signals;
    const bool par = ctx.size > 1;
    MPI_Comm comm = MPI_COMM_WORLD;
    // Every check comes before the file is changed: a refused run leaves it byte for byte.
    ctx.errors_collective = true;
    check_options(opt);
    if (::access(opt.file.c_str(), W_OK) != 0)
        throw InputError(fmt::format("{}: cannot write to this file ({}): pd-solve stores its "
                                     "frames in it; copy it somewhere writable",
                                     opt.file, std::strerror(errno)));
    // Phase 1, every rank: read the model (and the checkpoint) read-only. Up to phase 2 every
    // rank works on the same data, so every rank raises the same errors.
    ctx.errors_collective = true;
    model::Model m;
    std::optional<store::Checkpoint> ck;
    std::optional<store::Partition> part;
    double ck_read_seconds = 0;
    // Under MPI every rank reads the model without the bond list, then its own rows of it
    // (hyperslab reads) once its nodes are known.
    std::unique_ptr<solver::Domain> dom;
    std::vector<model::index_t> row_neighbors;
    {
        h5::File rf(opt.file, h5::Mode::read);
        m = store::read_model(rf, !par); // refuses a file it cannot read, untouched
        if (!opt.restart && !opt.overwrite)
            refuse_existing_results(rf, opt.file);
        if (opt.restart) {
            const double t0 = wall_seconds();
            ck = store::read_latest_checkpoint(rf, m.nodes.num(), m.bonds.num());
            ck_read_seconds = wall_seconds() - t0;
            if (!ck)
                throw InputError(fmt::format("{}: /checkpoints: no checkpoint to restart from "
                                             "(run pd-solve without --restart first)",
                                             opt.file));
        }
        if (par && rf.exists(store::path::partition)) {
            const auto by = rf.attr_string(store::path::partition, "by");
            auto p = store::read_partition(rf, by == "node" ? m.nodes.num() : m.bodies.num());
            if (p.num_parts == ctx.size)
                part = std::move(p);
        }
        // The ranks' nodes: /partition if it was made for this rank count, else a new one.
        if (par) {
            if (!part) {
                std::vector<std::int32_t> owner;
                int failed = 0;
                std::string why;
                if (ctx.rank == 0) { // METIS once (on the whole bond list), the same for all
                    try {
                        const model::Model whole = store::read_model(rf);
                        owner =
                            node_owner(whole, make_partition(whole, ctx.size, "auto", opt.file));
                    } catch (const std::exception& e) {
                        failed = 1;
                        why = e.what();
                    }
                }
                MPI_Bcast(&failed, 1, MPI_INT, 0, comm);
                if (failed)
                    throw InputError(ctx.rank == 0 ? why : "rank 0 could not partition the model");
                owner.resize(m.nodes.num());
                MPI_Bcast(owner.data(), static_cast<int>(owner.size()), MPI_INT32_T, 0, comm);
                dom = std::make_unique<solver::Domain>(comm, std::move(owner));
                ctx.log.info("/partition is missing or made for another rank count: partitioned "
                             "anew for {} ranks",
                             ctx.size);
            } else {
                dom = std::make_unique<solver::Domain>(comm, node_owner(m, *part));
                ctx.log.info("/partition: {} parts by {} (edge cut {}, imbalance {:.3f})",
                             part->num_parts, part->by, part->edge_cut, part->imbalance);
            }
            row_neighbors = store::read_bond_rows(rf, m, dom->runs());
        }
    }
    if (opt.final_time_given)
        m.solver.final_time = opt.final_time;

    solver::Solver s(m, dom.get(), std::move(row_neighbors));
    if (par) {
        const auto& domain = s.domain();
        // Work per rank: bonds plus nodes of the owned rows.
        double work = 0;
        for (auto i : domain.rows())
            work += 1.0 + static_cast<double>(m.bonds.offsets[static_cast<std::size_t>(i) + 1] -
                                              m.bonds.offsets[static_cast<std::size_t>(i)]);
        const double mean = domain.sum(work) / ctx.size;
        ctx.log.info("{} ranks: bond work imbalance (max/mean) {:.3f}; ghosts on rank 0: {} "
                     "nodes from {} neighbour ranks",
                     ctx.size, domain.max(work) / mean, domain.num_ghosts(),
                     domain.num_neighbours());
    }
    const auto est = s.stable_dt();
    double dt = m.solver.dt;
    if (ck) {
        dt = ck->dt; // the run continues with its own step
    } else if (dt == 0) {
        dt = m.solver.dt_safety * est.limit;
    } else if (dt > est.limit) {
        const std::string msg = fmt::format(
            "{}: /solver/dt = {:.4g} s exceeds the stability estimate {:.4g} s (governed by {}; "
            "bonds {:.4g} s, contact {:.4g} s)",
            opt.file, dt, est.limit, est.governing, est.pd, est.contact);
        if (!opt.force_dt)
            throw InputError(msg + "; lower dt, use \"auto\", or pass --force-dt");
        ctx.log.warn("{} (forced)", msg);
    }
    if (!std::isfinite(dt) || !(dt > 0))
        throw InputError(
            fmt::format("{}: no finite time step: set /solver/dt in the scene", opt.file));
    // The step count must fit a 64-bit integer (and a double's exact integers).
    const double steps_wanted = m.solver.final_time / dt;
    if (!(steps_wanted < 0x1p53))
        throw InputError(fmt::format(
            "{}: {} = {:.6g} s at dt = {:.4g} s is {:.3g} steps, more than a run can count "
            "(at most 2^53); give a smaller final time",
            opt.file, opt.final_time_given ? "--final-time" : "/solver/final_time",
            m.solver.final_time, dt, steps_wanted));
    std::int64_t total = 0;
    if (ck) {
        // Same dt; as many steps as reach final_time.
        total = static_cast<std::int64_t>(std::llround(m.solver.final_time / dt));
        if (total == ck->step) {
            // A run stopped (signal, pre-emption) after its last step: already complete. Its
            // requeued restart has nothing to do and changes nothing.
            ctx.log.info("{}: the checkpoint is at the final time t = {:.6g} s: the run is "
                         "complete, nothing to do",
                         opt.file, ck->time);
            return;
        }
        if (total < ck->step)
            throw InputError(fmt::format("{}: the checkpoint is at t = {:.6g} s, at or past the "
                                         "final time {:.6g} s (raise it with --final-time)",
                                         opt.file, ck->time, m.solver.final_time));
    } else {
        // A whole number of steps ending exactly at final_time.
        total = static_cast<std::int64_t>(std::ceil(m.solver.final_time / dt - 1e-9));
        dt = m.solver.final_time / static_cast<double>(total);
    }
    s.set_dt(dt);
    const std::int64_t first = ck ? ck->step : 0;
    const std::int64_t last =
        opt.max_steps >= 0 && opt.max_steps < total - first ? first + opt.max_steps : total;
    const std::int64_t out_every =
        m.solver.output_interval > 0
            ? std::max<std::int64_t>(1, std::llround(m.solver.output_interval / dt))
            : std::max<std::int64_t>(1, total);
    const std::int64_t ckpt_every =
        m.solver.checkpoint_interval > 0
            ? std::max<std::int64_t>(1, std::llround(m.solver.checkpoint_interval / dt))
            : std::numeric_limits<std::int64_t>::max();
    const std::int64_t obs_every = std::max<std::int64_t>(1, m.solver.observe_every);
    ctx.log.info(
        "{}: {} bodies, {} walls, {} nodes, {} bonds; dt = {:.4g} s ({:.3g} x stability "
        "limit {:.4g} s, governed by {}; bonds {:.4g} s, contact {:.4g} s), steps {} to {} "
        "(t = {:.4g} s), a frame every {} steps",
        opt.file, m.bodies.num(), m.walls.size(), m.nodes.num(), m.bonds.num(), dt, dt / est.limit,
        est.limit, est.governing, est.pd, est.contact, first, last, dt * static_cast<double>(last),
        out_every);
    if (!s.contact().active() && !s.walls().active())
        ctx.log.info("contact: off (no two bodies or walls with a contact law)");

    // Provenance: by rank 0 alone, once the run's (parallel) file is closed. Set only now: a
    // run refused by the checks above leaves the file as it was, byte for byte.
    ctx.on_exit = [&ctx, file = opt.file](int code) {
        if (ctx.rank != 0)
            return;
        h5::File f(file, h5::Mode::read_write);
        store::append_provenance(f, ctx.run, code);
    };
    // 16 MB set aside beside the file (rank 0): freed when a write fails on a full disk, so the
    // file still closes consistently with its last checkpoint (issue 13).
    SpaceReserve reserve;
    if (ctx.rank == 0)
        reserve = SpaceReserve::create(opt.file, std::uint64_t{16} << 20);
    // Phase 2, rank 0 alone: prepare the file (metadata only, serial).
    ctx.errors_collective = false;
    if (ctx.rank == 0) {
        h5::File wf(opt.file, h5::Mode::read_write);
        if (ck) {
            store::truncate_after(wf, ck->step);
        } else {
            // Fresh output: previous frames, observables and checkpoints are replaced.
            wf.remove(store::path::particles);
            wf.remove(store::path::observables);
            wf.remove(store::path::checkpoints);
            std::vector<double> mass(m.nodes.num());
            for (std::size_t i = 0; i < mass.size(); ++i)
                mass[i] = s.state().rho[i] * s.state().vol[i];
            store::write_particle_constants(wf, m.nodes.body, mass);
        }
    }
    if (par)
        MPI_Barrier(comm);
    // Phase 3, every rank: the run, on one file (MPI-IO, collective, under mpirun).
    auto f = std::make_unique<h5::File>(opt.file, h5::Mode::read_write, par ? &comm : nullptr);
    // Errors every rank sees alike (from reduced values, or from the same file) unwind on every
    // rank; any other error on one rank aborts them all rather than leaving them waiting.
    bool agreed = false;
    std::size_t nframes = 0;
    int stopped_by = 0;           // the signal that stopped the run early
    std::int64_t stopped_at = -1; // the step it stopped after (checkpointed)
    try {
        std::vector<double> damage, force;
        if (ck) {
            s.restore(ck->step, ck->time, ck->u, ck->v, ck->f, ck->alive, ck->broken_total);
            // The work is a sum over ranks: rank 0 carries what the checkpoint recorded.
            s.set_external_work(ctx.rank == 0 ? ck->external_work : 0.0,
                                ctx.rank == 0 ? ck->external_power : 0.0);
            if (ctx.rank == 0) {
                const auto& d = ck->dissipation;
                s.set_dissipation({d[0], d[1], d[2], d[3], d[4], d[5], d[6]});
            }
            ctx.log.info("restarted from the checkpoint at step {} (t = {:.6g} s; read in {:.3g} "
                         "s)",
                         ck->step, ck->time, ck_read_seconds);
            ck.reset();
        }
        store::FrameWriter frames(*f, m.nodes.num(), m.solver.fields, opt.compress);
        if (par)
            frames.set_runs(s.domain().runs());
        store::ObservableWriter obs(*f, s.num_walls(), s.reaction_bodies());
        if (first == 0) {
            s.initialize();
            if (s.precracked() > 0)
                ctx.log.info("pre-cracks: {} bonds start broken", s.precracked() / 2);
            write_frame(frames, s, damage, force);
            obs.add(0, 0.0, observable_row(s.observe()));
        }
        auto checkpoint = [&] {
            store::Checkpoint c;
            const auto& st = s.state();
            c.step = st.step;
            c.time = st.time;
            c.dt = dt;
            c.u = st.u;
            c.v = st.v;
            c.f = st.f;
            s.alive_into(c.alive); // this rank's entries; write_runs reads only those
            c.broken_total = s.broken_total();
            c.external_work = s.domain().sum(s.external_work());
            c.external_power = s.domain().sum(s.external_power_last());
            const auto& d = s.dissipation();
            std::vector<double> diss{d.fracture,     d.damping,       d.friction,    d.viscous,
                                     d.damping_rate, d.friction_rate, d.viscous_rate};
            s.domain().sum(diss);
            std::copy(diss.begin(), diss.end(), c.dissipation.begin());
            if (par) {
                c.node_runs = s.domain().runs();
                for (const auto& r : c.node_runs)
                    c.bond_runs.push_back({static_cast<std::uint64_t>(m.bonds.offsets[r[0]]),
                                           static_cast<std::uint64_t>(m.bonds.offsets[r[1]])});
            }
            store::write_checkpoint(*f, c);
        };
        double energy0 = 0, balance0 = 0, in_play = 0;
        if (first == 0) {
            const auto o = s.observe();
            energy0 = o.kinetic_energy + o.elastic_energy + o.contact_energy;
            balance0 = solver::energy_balance(o);
            in_play = solver::energy_in_play(o);
        } else {
            // Initial energy and balance from the first observable row (kept across restarts;
            // NaN in a file from before pd-file 1.2: no balance check), the energy in play as the
            // largest over the rows so far.
            auto series = store::read_observables(*f);
            auto at = [&](const char* name, std::size_t r) {
                const auto it = series.find(name);
                return it != series.end() && r < it->second.value.size()
                           ? it->second.value[r]
                           : std::numeric_limits<double>::quiet_NaN();
            };
            const auto ke = series.find("kinetic_energy");
            const std::size_t rows = ke != series.end() ? ke->second.value.size() : 0;
            for (std::size_t r = 0; r < rows; ++r) {
                solver::Observables o;
                o.kinetic_energy = at("kinetic_energy", r);
                o.elastic_energy = at("elastic_energy", r);
                o.contact_energy = at("contact_energy", r);
                o.external_work = at("external_work", r);
                o.fracture_energy = at("fracture_energy", r);
                o.damping_dissipation = at("damping_dissipation", r);
                o.friction_dissipation = at("friction_dissipation", r);
                o.viscous_dissipation = at("viscous_dissipation", r);
                if (r == 0) {
                    energy0 = o.kinetic_energy + o.elastic_energy + o.contact_energy;
                    balance0 = solver::energy_balance(o);
                }
                in_play = std::max(in_play, solver::energy_in_play(o));
            }
        }
        double next_report = wall_seconds() + opt.progress_seconds;
        double last_ck_wall = wall_seconds();
        s.timers().add(s.timers().id("pd::setup"), wall_seconds() - wall0); // read, build, t = 0
        Timers& timers = s.timers();
        const int t_out = timers.id("pd::store::output");
        const int t_ck = timers.id("pd::store::checkpoint");
        solver::Observables last_obs = s.observe();
        double busy_at_frame = 0, imbalance = 1.0; // compute time max/mean over ranks
        for (std::int64_t n = first + 1; n <= last; ++n) {
            const bool frame = n % out_every == 0 || n == total;
            // Not at the step a --steps run stops: a continued run has the rows of an uncut one.
            const bool observed = n % obs_every == 0 || frame;
            s.set_energies(observed); // bond energies only where a row is written
            s.advance();
            if (observed) {
                const auto o = s.observe(); // collective: every rank at the same steps
                last_obs = o;
                agreed = true; // the checks below see the same reduced values on every rank
                if (!std::isfinite(o.kinetic_energy) || !std::isfinite(o.elastic_energy) ||
                    !std::isfinite(o.contact_energy)) {
                    obs.flush();
                    const auto i = s.first_nonfinite();
                    throw NumericalError(fmt::format(
                        "{}: non-finite state at step {} (t = {:.6g} s){}; the last good frame "
                        "stays in the file. Lower dt (now {:.4g} s) or check the scene",
                        opt.file, n, s.state().time,
                        i >= 0 ? fmt::format(" at node {} of body {}", i,
                                             s.state().body[static_cast<std::size_t>(i)])
                               : std::string{},
                        dt));
                }
                // The fastest node of all ranks, for the messages below (collective).
                auto fastest = [&] {
                    const auto& st = s.state();
                    std::size_t fast = 0;
                    double vmax = -1;
                    for (auto row : st.rows) {
                        const auto i = static_cast<std::size_t>(row);
                        const double v = std::hypot(st.v[3 * i], st.v[3 * i + 1], st.v[3 * i + 2]);
                        if (v > vmax) {
                            vmax = v;
                            fast = i;
                        }
                    }
                    if (par) {
                        struct {
                            double v;
                            int i;
                        } mine{vmax, static_cast<int>(fast)}, all{};
                        MPI_Allreduce(&mine, &all, 1, MPI_DOUBLE_INT, MPI_MAXLOC, comm);
                        vmax = all.v;
                        fast = static_cast<std::size_t>(all.i);
                    }
                    return std::pair{fast, vmax};
                };
                // Blow-up: the mechanical energy far above what the system started with plus the
                // work done on it (it can only lose energy to damping and fracture).
                const double e = o.kinetic_energy + o.elastic_energy + o.contact_energy;
                if (e > 100.0 * (energy0 + std::max(0.0, o.external_work)) + 1e-300) {
                    obs.flush();
                    const auto& st = s.state();
                    const auto [fast, vmax] = fastest();
                    throw NumericalError(fmt::format(
                        "{}: blow-up at step {} (t = {:.6g} s): energy {:.4g} J against {:.4g} J "
                        "initial plus {:.4g} J of external work (fastest: node {} of body {}, "
                        "{:.3g} m/s); the last good frame stays in the file. Lower dt (now {:.4g} "
                        "s; "
                        "stability estimate {:.4g} s)",
                        opt.file, n, st.time, e, energy0, o.external_work, fast, st.body[fast],
                        vmax, dt, est.limit));
                }
                // Interpenetration: a node more than R_c + h/2 inside another grain.
                // A guard that fires keeps the row that failed in the file, then stops the run.
                auto stop = [&](const std::string& why) {
                    obs.add(n, s.state().time, observable_row(o));
                    obs.flush();
                    throw NumericalError(why);
                };
                if (opt.penetration_check && o.inside_pairs > 0) {
                    stop(fmt::format(
                        "{}: grains interpenetrate at step {} (t = {:.6g} s): {} node pair(s) "
                        "more than the contact radius + h/2 inside another grain{}. The contact "
                        "is too soft for this load or impact (raise contact.stiffness_factor or "
                        "the radius, slow the loading); the frames before stay in the file "
                        "(--no-penetration-check runs on)",
                        opt.file, n, s.state().time, o.inside_pairs,
                        o.inside_node >= 0 ? fmt::format(" (node {} of body {} inside body {})",
                                                         o.inside_node, o.inside_body, o.inside_of)
                                           : std::string{}));
                }
                if (opt.penetration_check && o.beyond_wall > 0) {
                    stop(fmt::format(
                        "{}: nodes pass through a rigid wall at step {} (t = {:.6g} s): {} "
                        "node(s) more than h/2 beyond a wall's surface{}. The wall contact is "
                        "too soft for this impact (raise contact.stiffness_factor, lower the "
                        "speed); the frames before stay in the file (--no-penetration-check "
                        "runs on)",
                        opt.file, n, s.state().time, o.beyond_wall,
                        o.beyond_node >= 0
                            ? fmt::format(" (node {} of body {}, wall {})", o.beyond_node,
                                          s.state().body[static_cast<std::size_t>(o.beyond_node)],
                                          o.beyond_wall_index)
                            : std::string{}));
                }
                // Energy balance: energy created (an instability, even one that fracture then
                // absorbs) or lost without account shows up here long before 100x.
                in_play = std::max(in_play, solver::energy_in_play(o));
                const double drift = solver::energy_balance(o) - balance0;
                if (opt.energy_tolerance > 0 && std::isfinite(balance0) &&
                    std::abs(drift) > opt.energy_tolerance * in_play && in_play > 0) {
                    obs.add(n, s.state().time, observable_row(o)); // the row that failed
                    obs.flush();
                    const auto [fast, vmax] = fastest();
                    throw NumericalError(fmt::format(
                        "{}: energy balance broken at step {} (t = {:.6g} s): KE + elastic + "
                        "contact + dissipated - external work moved by {:+.4g} J, {:.3g} % of the "
                        "{:.4g} J in play (tolerance {:.3g} %, --energy-tolerance; broken bonds "
                        "{}; fastest: node {} of body {}, {:.3g} m/s). The time step (now {:.4g} "
                        "s, stability estimate {:.4g} s) is too large or the model is unstable; "
                        "the frames before stay in the file",
                        opt.file, n, s.state().time, drift, 100 * std::abs(drift) / in_play,
                        in_play, 100 * opt.energy_tolerance, o.broken_bonds, fast,
                        s.state().body[fast], vmax, dt, est.limit));
                }
                obs.add(n, s.state().time, observable_row(o));
                agreed = false;
            }
            if (frame) {
                ScopedTimer t(timers, t_out);
                obs.flush();
                write_frame(frames, s, damage, force);
                if (par) { // work imbalance since the last frame (collective, as frames are)
                    const double now = busy_seconds(timers), mine = now - busy_at_frame;
                    busy_at_frame = now;
                    const double mean = s.domain().sum(mine) / ctx.size;
                    imbalance = mean > 0 ? s.domain().max(mine) / mean : 1.0;
                }
            }
            // A stop request (SIGTERM, SIGUSR1): every rank stops after the same step. Serial runs
            // look at every step, MPI runs every stop_check_every steps (collective).
            // The wall-time checkpoint (--checkpoint-every-wall) is decided with it, by rank 0's
            // clock.
            bool stop = false, wall_ck = false;
            if (n < last && (!par || n % stop_check_every == 0)) {
                int flags[2] = {static_cast<int>(stop_signal),
                                ctx.rank == 0 && opt.checkpoint_wall_seconds > 0 &&
                                    wall_seconds() - last_ck_wall >= opt.checkpoint_wall_seconds};
                if (par)
                    MPI_Allreduce(MPI_IN_PLACE, flags, 2, MPI_INT, MPI_MAX, comm);
                const int sig = flags[0];
                wall_ck = flags[1] != 0;
                if (sig != 0) {
                    stop = true;
                    stopped_by = sig;
                    stopped_at = n;
                }
            }
            if (n % ckpt_every == 0 || n == last || stop || wall_ck) {
                ScopedTimer t(timers, t_ck);
                obs.flush();
                checkpoint();
                last_ck_wall = wall_seconds();
            }
            if (stop)
                break;
            if (opt.rebalance && par && n % ckpt_every == 0 && n < last) {
                if (auto next = rebalance(m, s, dom->owner_map(), ctx, opt.file)) {
                    frames.set_runs(next->runs());
                    dom = std::move(next); // after s.redistribute(): the old one is done
                }
            }
            if (n == last || (wall_seconds() >= next_report && ctx.rank == 0)) {
                const auto& o = last_obs; // no collective call here: ranks differ in wall time
                const double el = wall_seconds() - wall0;
                const double done = static_cast<double>(n - first);
                ctx.log.info("step {}/{} t={:.4e} s dt={:.3e} s KE={:.4e} J broken={} contacts={} "
                             "wall={:.1f} s ETA={:.1f} s{}",
                             n, total, s.state().time, dt, o.kinetic_energy, o.broken_bonds,
                             o.contact_count, el, el / done * static_cast<double>(last - n),
                             par ? fmt::format(" imbalance={:.3f}", imbalance) : std::string{});
                next_report = wall_seconds() + opt.progress_seconds;
            }
        }
        obs.flush();
        nframes = frames.frames();
        f->close(); // checked: a write the disk refused (full) fails the run here, exit 2
    } catch (const std::exception& e) {
        reserve.release(); // room for HDF5 to flush and close the file (full disk)
        ctx.errors_collective = agreed;
        if (par && !agreed) {
            ctx.log.error(fmt::format("rank {}: {}", ctx.rank, e.what()));
            MPI_Abort(comm, dynamic_cast<const InputError*>(&e)       ? exit_input
                            : dynamic_cast<const NumericalError*>(&e) ? exit_numerical
                                                                      : exit_internal);
        }
        throw;
    }
    f.reset(); // collective close before rank 0 records provenance
    Timers& timers = s.timers();
    const double wall = wall_seconds() - wall0;
    const std::int64_t end = stopped_at >= 0 ? stopped_at : last;
    if (stopped_at >= 0) {
        // Every rank agreed on the step: the exit is collective, with its own code.
        ctx.errors_collective = true;
        ctx.exit_code = exit_preempted;
        if (ctx.rank == 0)
            ctx.log.warn("{}: stopped by {} after step {} of {} (t = {:.6g} s): checkpoint "
                         "written; continue with pd-solve --restart (exit {})",
                         opt.file, stopped_by == SIGUSR1 ? "SIGUSR1" : "SIGTERM", stopped_at, total,
                         s.state().time, static_cast<int>(exit_preempted));
    }
    ctx.log.info("done: steps {} to {}, {} frames in the file, {} contact-list rebuilds, {:.3g} "
                 "node-steps/s",
                 first, end, nframes, s.contact().rebuilds(),
                 static_cast<double>(m.nodes.num()) * static_cast<double>(end - first) / wall);
    if (par) {
        // Load balance over the run: time in force evaluation and integration per rank.
        const double busy = busy_seconds(timers);
        const auto& domain = s.domain();
        const double mean = domain.sum(busy) / ctx.size;
        ctx.log.info("load balance: compute time max/mean over {} ranks {:.3f} (mean {:.3g} s of "
                     "{:.3g} s wall)",
                     ctx.size, mean > 0 ? domain.max(busy) / mean : 1.0, mean, wall);
    }
    ctx.log.info("{}", timers.table(wall));
}

} // namespace pd::pipeline
