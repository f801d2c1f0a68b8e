// SPDX-License-Identifier: MIT
// pd-solve: the run in four phases. Open: read the model (and the checkpoint) read-only, every
// check before the file changes. Set up: the solver, the time step, the step counts, the file
// prepared by rank 0. Run: the step loop, a short loop over the scheduled actions of
// run/actions.def (frames, observables, checkpoints, guards, ...). Close: the report.
#include "pipeline/solve.hpp"

#include "core/errors.hpp"
#include "core/file_lock.hpp"
#include "core/timer.hpp"
#include "h5/file.hpp"
#include "pipeline/full_disk.hpp"
#include "pipeline/partition.hpp"
#include "pipeline/rank_report.hpp"
#include "pipeline/restart_changes.hpp"
#include "pipeline/run/schedule.hpp"
#include "pipeline/run/signals.hpp"
#include "pipeline/simulation.hpp"
#include "pipeline/solve_checks.hpp"
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
#include <memory>
#include <optional>
#include <unistd.h>

namespace pd::pipeline {

namespace {

/// What the open phase read (every rank alike, up to this rank's rows of the bond list).
struct Input {
    model::Model m;
    std::optional<store::Checkpoint> ck;
    double ck_read_seconds = 0;
    std::unique_ptr<solver::Domain> dom; ///< MPI: this rank's nodes
    std::vector<model::index_t> row_neighbors;
};

/// The ranks' nodes: /partition if it was made for this rank count, else a new one (METIS once
/// on rank 0, on the whole bond list, the same for all).
std::unique_ptr<solver::Domain> ranks_domain(const h5::File& rf, const model::Model& m,
                                             const SolveOptions& opt, Context& ctx) {
    MPI_Comm comm = MPI_COMM_WORLD;
    std::optional<store::Partition> part;
    if (rf.exists(store::path::partition)) {
        const auto by = rf.attr_string(store::path::partition, "by");
        auto p = store::read_partition(rf, by == "node" ? m.nodes.num() : m.bodies.num());
        if (p.num_parts == ctx.size)
            part = std::move(p);
    }
    if (part) {
        auto dom = std::make_unique<solver::Domain>(comm, node_owner(m, *part));
        ctx.log.info("/partition: {} parts by {} (edge cut {}, imbalance {:.3f})", part->num_parts,
                     part->by, part->edge_cut, part->imbalance);
        return dom;
    }
    std::vector<std::int32_t> owner;
    int failed = 0;
    std::string why;
    if (ctx.rank == 0) {
        try {
            const model::Model whole = store::read_model(rf);
            owner = node_owner(whole, make_partition(whole, ctx.size, "auto", opt.file));
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
    ctx.log.info("/partition is missing or made for another rank count: partitioned "
                 "anew for {} ranks",
                 ctx.size);
    return std::make_unique<solver::Domain>(comm, std::move(owner));
}

/// Phase 1, every rank: the model (and the checkpoint, with --set's changes) read-only; every
/// rank raises the same errors. The model without its neighbour lists, then this rank's rows
/// of them (all rows on one rank).
Input open(const SolveOptions& opt, Context& ctx) {
    const bool par = ctx.size > 1;
    // Every check comes before the file is changed: a refused run leaves it byte for byte.
    ctx.errors_collective = true;
    check_options(opt);
    if (::access(opt.file.c_str(), W_OK) != 0)
        throw InputError(fmt::format("{}: cannot write to this file ({}): pd-solve stores its "
                                     "frames in it; copy it somewhere writable",
                                     opt.file, std::strerror(errno)));
    Input in;
    h5::File rf(opt.file, h5::Mode::read);
    // Without the neighbour lists: the solver keeps this rank's rows, read below (one copy of
    // them, not two, at one rank too: 4 bytes per bond).
    in.m = store::read_model(rf, false); // refuses a file it cannot read, untouched
    if (!opt.restart && !opt.overwrite)
        refuse_existing_results(rf, opt.file);
    if (opt.restart) {
        const double t0 = wall_seconds();
        in.ck = store::read_latest_checkpoint(rf, in.m.nodes.num(), in.m.bonds.num());
        in.ck_read_seconds = wall_seconds() - t0;
        if (!in.ck)
            throw InputError(fmt::format("{}: /checkpoints: no checkpoint to restart from "
                                         "(run pd-solve without --restart first)",
                                         opt.file));
        ctx.run.overrides = apply_restart_changes(in.m, opt.sets, in.ck->u, in.ck->time, opt.file);
    }
    if (par)
        in.dom = ranks_domain(rf, in.m, opt, ctx);
    in.row_neighbors = store::read_bond_rows(
        rf, in.m,
        par ? in.dom->runs() : std::vector<std::array<std::uint64_t, 2>>{{0, in.m.nodes.num()}});
    if (opt.final_time_given)
        in.m.solver.final_time = opt.final_time;
    return in;
}

/// Work per rank: bonds plus nodes of the owned rows (MPI).
void log_work_balance(const model::Model& m, const solver::Solver& s, Context& ctx) {
    const auto& domain = s.domain();
    double work = 0;
    for (auto i : domain.rows())
        work += 1.0 + static_cast<double>(m.bonds.offsets[static_cast<std::size_t>(i) + 1] -
                                          m.bonds.offsets[static_cast<std::size_t>(i)]);
    const double mean = domain.sum(work) / ctx.size;
    ctx.log.info("{} ranks: bond work imbalance (max/mean) {:.3f}; ghosts on rank 0: {} "
                 "nodes from {} neighbour ranks",
                 ctx.size, domain.max(work) / mean, domain.num_ghosts(), domain.num_neighbours());
}

/// The time step: the checkpoint's on a restart (the run continues with its own step), else the
/// scene's, checked against the stability estimate, or dt_safety x the estimate ("auto").
double time_step(const SolveOptions& opt, Context& ctx, const Input& in,
                 const solver::StableDt& est) {
    const auto& m = in.m;
    double dt = m.solver.dt;
    if (in.ck) {
        dt = in.ck->dt; // the run continues with its own step
    } else if (dt == 0) {
        dt = m.solver.dt_safety * est.limit;
    } else if (dt > est.limit) {
        const std::string msg = fmt::format(
            "{}: /solver/dt = {:.4g} s exceeds the stability estimate {:.4g} s (governed by {}; "
            "bonds {:.4g} s, contact {:.4g} s)",
            opt.file, dt, est.limit, est.governing, est.pd, est.contact);
        if (!opt.force_dt && !m.solver.dt_above_estimate_warns)
            throw InputError(msg + "; lower dt, use \"auto\", or pass --force-dt");
        ctx.log.warn("{} ({})", msg, opt.force_dt ? "forced" : "solver.dt_above_estimate: warn");
    }
    if (!std::isfinite(dt) || !(dt > 0))
        throw InputError(
            fmt::format("{}: no finite time step: set /solver/dt in the scene", opt.file));
    return dt;
}

/// The steps of this invocation and the intervals of the scheduled actions; nullopt when a
/// restart finds the run complete.
std::optional<run::Steps> count_steps(const SolveOptions& opt, Context& ctx, const Input& in,
                                      double dt) {
    const auto& m = in.m;
    const auto& ck = in.ck;
    // The step count must fit a 64-bit integer (and a double's exact integers).
    const double steps_wanted = m.solver.final_time / dt;
    if (!(steps_wanted < 0x1p53))
        throw InputError(fmt::format(
            "{}: {} = {:.6g} s at dt = {:.4g} s is {:.3g} steps, more than a run can count "
            "(at most 2^53); give a smaller final time",
            opt.file, opt.final_time_given ? "--final-time" : "/solver/final_time",
            m.solver.final_time, dt, steps_wanted));
    run::Steps st;
    if (ck) {
        // Same dt; as many steps as reach final_time.
        st.total = static_cast<std::int64_t>(std::llround(m.solver.final_time / dt));
        if (st.total == ck->step) {
            // A run stopped (signal, pre-emption) after its last step: already complete. Its
            // requeued restart has nothing to do and changes nothing.
            ctx.log.info("{}: the checkpoint is at the final time t = {:.6g} s: the run is "
                         "complete, nothing to do",
                         opt.file, ck->time);
            return std::nullopt;
        }
        if (st.total < ck->step)
            throw InputError(fmt::format("{}: the checkpoint is at t = {:.6g} s, at or past the "
                                         "final time {:.6g} s (raise it with --final-time)",
                                         opt.file, ck->time, m.solver.final_time));
    } else {
        // A whole number of steps ending exactly at final_time.
        st.total = static_cast<std::int64_t>(std::ceil(m.solver.final_time / dt - 1e-9));
        dt = m.solver.final_time / static_cast<double>(st.total);
    }
    st.dt = dt;
    st.first = ck ? ck->step : 0;
    st.last = opt.max_steps >= 0 && opt.max_steps < st.total - st.first ? st.first + opt.max_steps
                                                                        : st.total;
    st.out_every = m.solver.output_interval > 0
                       ? std::max<std::int64_t>(1, std::llround(m.solver.output_interval / dt))
                       : std::max<std::int64_t>(1, st.total);
    st.ckpt_every = m.solver.checkpoint_interval > 0
                        ? std::max<std::int64_t>(1, std::llround(m.solver.checkpoint_interval / dt))
                        : std::numeric_limits<std::int64_t>::max();
    st.obs_every = std::max<std::int64_t>(1, m.solver.observe_every);
    return st;
}

/// Phase 2, rank 0 alone: prepare the file (metadata only, serial).
void prepare_file(const SolveOptions& opt, Context& ctx, const Input& in, const solver::Solver& s,
                  SpaceReserve& reserve) {
    // Rank 0 holds the file's lock from here to the end of its provenance record: the other
    // ranks' shared holds (released as they leave, in any order) never make the record wait
    // or fail, and no other tool can slip in between the run and its record.
    auto held =
        std::make_shared<FileLock>(ctx.rank == 0 ? FileLock::acquire(opt.file) : FileLock());
    // 16 MB beside the file (rank 0), freed when a write fails on a full disk (issue 13).
    if (ctx.rank == 0)
        reserve = SpaceReserve::create(opt.file, std::uint64_t{16} << 20);
    // Provenance: rank 0, once the parallel file is closed. Set only now, as the run starts
    // changing the file: a run refused before leaves the file as it was, byte for byte. A file
    // renamed, removed or replaced during the run gets no record (was: exit 4).
    const auto id = ctx.rank == 0 ? file_identity(opt.file) : std::array<std::uint64_t, 2>{};
    ctx.on_exit = [&ctx, file = opt.file, held, id](int code) {
        if (ctx.rank != 0)
            return;
        if (file_identity(file) != id) {
            ctx.log.warn("{}: renamed, removed or replaced during the run: the run is not "
                         "recorded in its /provenance",
                         file);
            return;
        }
        h5::File f(file, h5::Mode::read_write);
        store::append_provenance(f, ctx.run, code);
    };
    ctx.errors_collective = false;
    if (ctx.rank == 0) {
        h5::File wf(opt.file, h5::Mode::read_write);
        if (in.ck) {
            store::truncate_after(wf, in.ck->step);
            if (!opt.sets.empty()) // the changed walls and loading (restart_changes.hpp)
                store::write_walls_and_loading(wf, in.m);
        } else {
            // Fresh output: previous frames, observables and checkpoints are replaced.
            wf.remove(store::path::particles);
            wf.remove(store::path::observables);
            wf.remove(store::path::checkpoints);
            std::vector<double> mass(in.m.nodes.num());
            for (std::size_t i = 0; i < mass.size(); ++i)
                mass[i] = s.state().rho[i] * s.state().vol[i];
            store::write_particle_constants(wf, in.m.nodes.body, mass);
        }
    }
    if (ctx.size > 1)
        MPI_Barrier(MPI_COMM_WORLD);
}

/// The state of a restart: the checkpoint's (read in phase 1), then freed.
void restore(Context& ctx, Input& in, solver::Solver& s) {
    const auto& ck = *in.ck;
    s.restore(ck.step, ck.time, ck.u, ck.v, ck.f, ck.alive, ck.broken_total);
    if (ck.depth_time >= 0) // the surface law's depth history: the run decides as it would have
        s.set_surface_depths(ck.depth_pairs, ck.depths, ck.depth_time);
    if (!ck.build_x.empty()) // and its last contact-list rebuild: the rebuilds fall as they did
        s.restore_surface_build(ck.build_x, ck.build_whole);
    // The work is a sum over ranks: rank 0 carries what the checkpoint recorded.
    s.set_external_work(ctx.rank == 0 ? ck.external_work : 0.0,
                        ctx.rank == 0 ? ck.external_power : 0.0);
    if (ctx.rank == 0) {
        const auto& d = ck.dissipation;
        s.set_dissipation({d[0], d[1], d[2], d[3], d[4], d[5], d[6]});
    }
    // The open observation interval's reaction sums: rank 0 carries the ranks' total.
    auto sum = ck.interval_sum;
    if (ctx.rank != 0)
        std::fill(sum.begin(), sum.end(), 0.0);
    s.set_interval(std::move(sum), ck.interval_steps);
    ctx.log.info("restarted from the checkpoint at step {} (t = {:.6g} s; read in {:.3g} s)",
                 ck.step, ck.time, in.ck_read_seconds);
    in.ck.reset();
}

/// How the run phase ended.
struct Outcome {
    std::size_t nframes = 0;
    int stopped_by = 0;           ///< the signal that stopped the run early
    std::int64_t stopped_at = -1; ///< the step it stopped after (checkpointed)
    std::int64_t end = 0;         ///< the last step done
};

/// The close: the stop (exit_preempted, every rank agreed on the step), the run's figures.
void report(const SolveOptions& opt, Context& ctx, const model::Model& m, solver::Solver& s,
            const run::Steps& st, const Outcome& out, double wall0) {
    Timers& timers = s.timers();
    const double wall = wall_seconds() - wall0;
    const std::int64_t end = out.end;
    if (out.stopped_at >= 0) {
        // Every rank agreed on the step: the exit is collective, with its own code.
        ctx.errors_collective = true;
        ctx.exit_code = exit_preempted;
        if (ctx.rank == 0)
            ctx.log.warn("{}: stopped by {} after step {} of {} (t = {:.6g} s): checkpoint "
                         "written; continue with pd-solve --restart (exit {})",
                         opt.file, run::stop_signal_name(out.stopped_by), out.stopped_at, st.total,
                         s.state().time, static_cast<int>(exit_preempted));
    }
    ctx.log.info("done: steps {} to {}, {} frames in the file, {} contact-list rebuilds, {:.3g} "
                 "node-steps/s",
                 st.first, end, out.nframes, s.contact().rebuilds(),
                 static_cast<double>(m.nodes.num()) * static_cast<double>(end - st.first) / wall);
    if (ctx.size > 1) {
        // Load balance over the run: time in force evaluation and integration per rank.
        const double busy = run::busy_seconds(timers);
        const auto& domain = s.domain();
        const double mean = domain.sum(busy) / ctx.size;
        ctx.log.info("load balance: compute time max/mean over {} ranks {:.3f} (mean {:.3g} s of "
                     "{:.3g} s wall)",
                     ctx.size, mean > 0 ? domain.max(busy) / mean : 1.0, mean, wall);
    }
    ctx.log.info("{}", timers.table(wall));
}

} // namespace

/// The run between its set-up and its close: what pd-solve's phases hold.
struct Simulation::Impl {
    SolveOptions opt;
    Context& ctx;
    double wall0 = 0;
    Input in;
    std::unique_ptr<solver::Solver> s;
    run::Steps st;
    SimulationSteps pub;
    bool complete = false; ///< a restart of a complete run: nothing to do
    SpaceReserve reserve;
    bool par = false;
    MPI_Comm comm = MPI_COMM_WORLD;
    std::unique_ptr<h5::File> f;
    bool agreed = false;
    std::unique_ptr<store::FrameWriter> frames;
    std::unique_ptr<store::ObservableWriter> obs;
    std::unique_ptr<run::Run> r;
    std::unique_ptr<run::Schedule> schedule;
    std::int64_t n = 0;   ///< the step the state is at
    bool stopped = false; ///< a stop request ended the loop
    bool closed = false;
    RankMark loop0; ///< the counters as the step loop starts (rank_report)

    Impl(const SolveOptions& o, Context& c)
        : opt(o)
        , ctx(c) {}

    /// Phase 3's errors: those every rank sees alike unwind; any other one aborts the ranks.
    void fail(const std::exception& e) {
        // Under MPI only the check before a write (every rank alike, nothing written) is a full
        // disk that can be recovered; a serial run also after the write the disk refused.
        const bool every_rank = dynamic_cast<const DiskFullError*>(&e) != nullptr;
        const bool full = every_rank || (!par && f && disk_full(e, opt.file));
        reserve.release(); // room for HDF5 to flush and close the file (full disk)
        ctx.errors_collective = agreed || every_rank;
        if (full) {
            closed = true; // the file is closed here: the destructor must not close the run again
            if (par)
                end_on_full_disk(f, opt.file, e, comm, ctx.rank); // throws, on every rank
            end_on_full_disk(*f, e); // throws: the file cut back to its latest checkpoint
        }
        if (par && !agreed) {
            ctx.log.error(fmt::format("rank {}: {}", ctx.rank, e.what()));
            MPI_Abort(comm, dynamic_cast<const InputError*>(&e)       ? exit_input
                            : dynamic_cast<const NumericalError*>(&e) ? exit_numerical
                                                                      : exit_internal);
        }
    }

    /// Phase 3 up to the loop, every rank on one file (MPI-IO, collective, under mpirun): the
    /// checkpoint restored or t = 0 written, the scheduled actions built.
    void start() {
        f = std::make_unique<h5::File>(opt.file, h5::Mode::read_write, par ? &comm : nullptr);
        try {
            if (in.ck)
                restore(ctx, in, *s);
            frames = std::make_unique<store::FrameWriter>(*f, in.m.nodes.num(), in.m.solver.fields,
                                                          opt.compress);
            if (par)
                frames->set_runs(s->domain().runs());
            obs =
                std::make_unique<store::ObservableWriter>(*f, s->num_walls(), s->reaction_bodies());
            r.reset(new run::Run{.opt = opt,
                                 .ctx = ctx,
                                 .m = in.m,
                                 .s = *s,
                                 .dom = in.dom,
                                 .file = *f,
                                 .frames = *frames,
                                 .obs = *obs,
                                 .steps = st,
                                 .wall0 = wall0,
                                 .agreed = agreed,
                                 .par = par,
                                 .comm = comm});
            if (st.first == 0) {
                s->initialize();
                if (s->precracked() > 0)
                    ctx.log.info("pre-cracks: {} bonds start broken", s->precracked() / 2);
                run::write_frame(*r);
                r->obs.add(0, 0.0, run::observable_row(s->observe()));
            }
            Timers& timers = s->timers();
            const int t_setup = timers.id("pd::setup");
            schedule = std::make_unique<run::Schedule>(*r);
            timers.add(t_setup, wall_seconds() - wall0); // read, build, t = 0
            r->last_obs = s->observe();
            n = st.first;
            loop0 = mark_rank(*s);
        } catch (const std::exception& e) {
            fail(e);
            throw;
        }
    }
};

Simulation::Simulation(const SolveOptions& opt, Context& ctx)
    : impl_(std::make_unique<Impl>(opt, ctx)) {
    auto& p = *impl_;
    p.wall0 = wall_seconds();
    p.par = ctx.size > 1;
    ctx.log.info("{} rank{} x {} thread{} ({})", ctx.size, ctx.size == 1 ? "" : "s",
                 ctx.run.threads, ctx.run.threads == 1 ? "" : "s", ctx.run.threads_why);
    p.in = open(p.opt, ctx); // Open, then set up:
    p.s = std::make_unique<solver::Solver>(p.in.m, p.in.dom.get(), std::move(p.in.row_neighbors));
    auto& s = *p.s;
    if (ctx.size > 1)
        log_work_balance(p.in.m, s, ctx);
    const auto est = s.stable_dt();
    const auto steps = count_steps(p.opt, ctx, p.in, time_step(p.opt, ctx, p.in, est));
    if (!steps) {
        p.complete = true; // a restart of a complete run
        p.closed = true;
        return;
    }
    s.set_dt(steps->dt);
    p.st = *steps;
    p.st.est = est;
    auto& st = p.st;
    p.pub = {st.dt, st.first, st.last, st.total, st.out_every, st.ckpt_every, st.obs_every};
    const auto& m = p.in.m;
    ctx.log.info(
        "{}: {} bodies, {} walls, {} nodes, {} bonds; dt = {:.4g} s ({:.3g} x stability "
        "limit {:.4g} s, governed by {}; bonds {:.4g} s, contact {:.4g} s), steps {} to {} "
        "(t = {:.4g} s), a frame every {} steps",
        p.opt.file, m.bodies.num(), m.walls.size(), m.nodes.num(), m.bonds.num(), st.dt,
        st.dt / est.limit, est.limit, est.governing, est.pd, est.contact, st.first, st.last,
        st.dt * static_cast<double>(st.last), st.out_every);
    if (!s.contact().active() && !s.walls().active())
        ctx.log.info("contact: off (no two bodies or walls with a contact law)");
    prepare_file(p.opt, ctx, p.in, s, p.reserve);
    // Run: up to the step loop.
    p.start();
}

Simulation::~Simulation() {
    if (!impl_ || impl_->closed)
        return;
    try {
        close();
    } catch (const std::exception& e) {
        impl_->ctx.log.error(std::string("while closing the run: ") + e.what());
    }
}

std::int64_t Simulation::advance(std::int64_t k) {
    auto& p = *impl_;
    std::int64_t done = 0;
    if (finished())
        return 0;
    try {
        auto& s = *p.s;
        auto& schedule = *p.schedule;
        for (; done < k && p.n < p.st.last; ++done) {
            const std::int64_t n = p.n + 1;
            s.set_energies(schedule.needs_energies(n)); // bond energies only where observed
            s.advance();
            p.n = n;
            if (!schedule.after_step(*p.r, n)) {
                p.stopped = true;
                ++done;
                break;
            }
        }
    } catch (const std::exception& e) {
        p.fail(e);
        throw;
    }
    return done;
}

bool Simulation::finished() const {
    const auto& p = *impl_;
    return p.complete || p.closed || p.stopped || p.n >= p.st.last;
}

std::int64_t Simulation::step() const {
    return impl_->complete ? impl_->s->state().step : impl_->n;
}

void Simulation::checkpoint() {
    auto& p = *impl_;
    if (p.complete || p.closed)
        return;
    try {
        run::ensure_room(*p.r, false, true);
        p.obs->flush();
        run::checkpoint_now(*p.r);
    } catch (const std::exception& e) {
        p.fail(e);
        throw;
    }
}

int Simulation::close() {
    auto& p = *impl_;
    if (p.closed)
        return p.ctx.exit_code;
    p.closed = true;
    Outcome out;
    try {
        // A driven run that ends before its last step leaves a checkpoint to continue from.
        if (!p.stopped && p.n < p.st.last && p.n > p.st.first) {
            run::ensure_room(*p.r, false, true);
            p.obs->flush();
            run::checkpoint_now(*p.r);
        }
        out.stopped_by = p.r->stopped_by;
        out.stopped_at = p.r->stopped_at;
        out.end = p.n;
        p.obs->flush();
        out.nframes = p.frames->frames();
        p.f->close(); // checked: a write the disk refused (full) fails the run here, exit 2
    } catch (const std::exception& e) {
        p.fail(e);
        throw;
    }
    p.schedule.reset();
    p.r.reset();
    p.obs.reset();
    p.frames.reset();
    p.f.reset(); // collective close before rank 0 records provenance
    // Close.
    report(p.opt, p.ctx, p.in.m, *p.s, p.st, out, p.wall0);
    report_ranks(p.ctx, *p.s, p.loop0, out.end - p.st.first);
    return p.ctx.exit_code;
}

void Simulation::abandon() {
    auto& p = *impl_;
    p.closed = true;
    p.schedule.reset();
    p.r.reset();
    p.obs.reset();
    p.frames.reset();
    p.f.reset();
}

solver::Solver& Simulation::solver() {
    return *impl_->s;
}

const model::Model& Simulation::model() const {
    return impl_->in.m;
}

const SimulationSteps& Simulation::steps() const {
    return impl_->pub;
}

void solve(const SolveOptions& opt, Context& ctx) {
    const run::StopSignals stop_signals;
    Simulation sim(opt, ctx);
    if (sim.finished())
        return; // a restart of a complete run
    sim.advance(std::numeric_limits<std::int64_t>::max());
    sim.close();
}

} // namespace pd::pipeline
