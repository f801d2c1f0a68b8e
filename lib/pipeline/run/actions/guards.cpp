// SPDX-License-Identifier: MIT
// The run's guards, at the observed steps: a non-finite state, a blow-up, interpenetration, a
// node through a rigid wall, a broken energy balance each stop the run (NumericalError, exit 3)
// with the frames before in the file and the state at the failing step as a last frame, flagged
// (/particles/nodes attributes failed_step, failure; issue 28). Every rank sees the same reduced
// values: the error unwinds on every rank alike.
#include "core/errors.hpp"
#include "h5/file.hpp"
#include "pipeline/run/schedule.hpp"
#include "solver/walls.hpp"
#include "store/frames.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace pd::pipeline::run {

namespace {

/// The fastest node of all ranks, for the messages (collective).
std::pair<std::size_t, double> fastest(const Run& r) {
    const auto& st = r.s.state();
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
    if (r.par) {
        struct {
            double v;
            int i;
        } mine{vmax, static_cast<int>(fast)}, all{};
        MPI_Allreduce(&mine, &all, 1, MPI_DOUBLE_INT, MPI_MAXLOC, r.comm);
        vmax = all.v;
        fast = static_cast<std::size_t>(all.i);
    }
    return {fast, vmax};
}

/// The state at the failing step as the last frame, flagged with the guard's `kind` (the same
/// on every rank: the attribute write is collective under MPI-IO).
void failed_frame(Run& r, std::int64_t n, const char* kind) {
    ensure_room(r, true, false);
    r.obs.flush();
    write_frame(r);
    r.frames.flag_failed(n, kind);
}

/// A guard that fires keeps the row that failed and the state in the file, then stops the run.
[[noreturn]] void stop_with_row(Run& r, std::int64_t n, const char* kind, const std::string& why) {
    r.obs.add(n, r.s.state().time, observable_row(r.last_obs));
    failed_frame(r, n, kind);
    throw NumericalError(why);
}

double distance(const double* a, const double* b) {
    return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

/// How deep node `i` (its current position) is inside body `b`, m: the largest over the nodes j
/// of b near it of (the reference depth of j - |y_i - y_j|). A node below b's surface layer
/// (pd-pack's /nodes/surface, `layer` thick) is at least `layer` plus its reference distance to
/// the layer deep; a layer node counts 0 (a lower bound, as check_run.py's, sharp to about h/2).
double depth_inside(const Run& r, std::int64_t i, std::int32_t b, double layer) {
    const auto& st = r.s.state();
    const auto& nodes = r.m.nodes;
    const auto& B = r.m.bodies;
    const double h = B.mesh_size[static_cast<std::size_t>(b)];
    const double* yi = &st.x[3 * static_cast<std::size_t>(i)];
    std::vector<std::size_t> near, layer_nodes;
    for (auto j = B.begin(static_cast<std::size_t>(b)); j < B.end(static_cast<std::size_t>(b));
         ++j) {
        const auto J = static_cast<std::size_t>(j);
        if (nodes.surface.empty() || nodes.surface[J])
            layer_nodes.push_back(J);
        else if (distance(yi, &st.x[3 * J]) < 2 * h)
            near.push_back(J);
    }
    double depth = -std::numeric_limits<double>::infinity();
    for (auto J : near) {
        double s = std::numeric_limits<double>::infinity();
        for (auto K : layer_nodes)
            s = std::min(s, distance(&nodes.x0[3 * J], &nodes.x0[3 * K]));
        if (std::isfinite(s))
            depth = std::max(depth, layer + s - distance(yi, &st.x[3 * J]));
    }
    return depth;
}

/// The contact law between bodies a and b (nullptr: none).
const model::ContactPair* law_between(const model::Model& m, std::int32_t a, std::int32_t b) {
    const auto ga = m.bodies.group[static_cast<std::size_t>(a)];
    const auto gb = m.bodies.group[static_cast<std::size_t>(b)];
    for (const auto& p : m.contact)
        if ((p.group_a == ga && p.group_b == gb) || (p.group_a == gb && p.group_b == ga))
            return &p;
    return nullptr;
}

/// The numbers of an interpenetration: depth reached (the largest over the ranks that saw a
/// node), R_c and h of the pair, K_n, dt and its limits (collective under MPI).
/// What the interpenetration message says: the numbers, and whether the law between the two
/// bodies is the surface law (no radius: its bound is h/2 behind the boundary).
struct PenetrationReport {
    std::string numbers;
    bool surface = false;
};

PenetrationReport penetration_numbers(const Run& r) {
    const auto& o = r.last_obs;
    double rc_max = 0;
    for (const auto& p : r.m.contact)
        rc_max = std::max(rc_max, p.radius);
    double depth = -std::numeric_limits<double>::infinity(), rc = 0, kn = 0, h = 0, surf = 0;
    if (o.inside_node >= 0 && o.inside_of >= 0) {
        h = r.m.bodies.mesh_size[static_cast<std::size_t>(o.inside_of)];
        const double layer = rc_max + 0.5 * h + std::min(rc_max, h);
        depth = depth_inside(r, o.inside_node, o.inside_of, layer);
        if (const auto* p = law_between(r.m, o.inside_body, o.inside_of)) {
            surf = p->law == model::ContactLaw::surface ? 1 : 0;
            rc = surf > 0 ? 0.0 : p->radius;
            kn = p->stiffness;
        }
    }
    if (r.par) {
        double mine[5] = {depth, rc, kn, h, surf}, all[5];
        MPI_Allreduce(mine, all, 5, MPI_DOUBLE, MPI_MAX, r.comm);
        depth = all[0], rc = all[1], kn = all[2], h = all[3], surf = all[4];
    }
    // A contact far softer than the grains (its stable step 10x the bonds'; the default K_n
    // gives about 1-2x) is the first suspect, beside the radius.
    const double soft = r.steps.est.pd > 0 ? r.steps.est.contact / r.steps.est.pd : 0;
    const std::string softer =
        soft > 10 ? fmt::format("; the contact is far softer than the grains (its stable step is "
                                "{:.3g} x the bonds'): check contact.stiffness and "
                                "stiffness_factor",
                                soft)
                  : std::string{};
    const std::string reached =
        std::isfinite(depth) ? fmt::format("{:.4g} m", depth) : std::string("unknown");
    const std::string law =
        surf > 0 ? fmt::format("depth reached {} (surface law, h = {:.4g} m: the guard's bound "
                               "h/2 = {:.4g} m), c = {:.4g} N m-5",
                               reached, h, 0.5 * h, kn)
                 : fmt::format("depth reached {} (R_c = {:.4g} m, h = {:.4g} m: the guard's "
                               "bound R_c + h/2 = {:.4g} m), K_n = {:.4g} N m-7",
                               reached, rc, h, rc + 0.5 * h, kn);
    return {law +
                fmt::format(", dt = {:.4g} s (stability limit {:.4g} s: bonds {:.4g} s, "
                            "contact {:.4g} s)",
                            r.steps.dt, r.steps.est.limit, r.steps.est.pd, r.steps.est.contact) +
                softer,
            surf > 0};
}

/// The fastest closing motion the contact search must see within one step (collective; every
/// rank gets the same answer from min/max reductions, whatever the rank count).
/// - Between bodies: each node's speed relative to the centre c of the box of all node
///   velocities (component-wise min and max over every rank's nodes). Safe because for any
///   pair |v_i - v_j| = |(v_i - c) - (v_j - c)| <= 2 max_k |v_k - c| (<= the box's diagonal): if
///   every node moves less than R_c per step relative to c, no pair closes by 2 R_c (the width
///   of the contact zone) in one step -- the bound the absolute speed gave, now unchanged by a
///   translation of the whole system (two discs flying together at 1e5 m/s run).
/// - Against a rigid wall (moving or not): the node's velocity relative to the wall's surface
///   velocity at the node (translation plus rotation about its centre), for the walls the node's
///   group has a contact law with, once present: a node closing on a wall by R_c per step (the
///   zone is R_c deep on one side) passes it unseen.
struct Closing {
    double speed = -1;                     ///< m s-1
    std::size_t node = 0;                  ///< the node that has it
    int wall = -1;                         ///< -1: relative to the velocity centre of the bodies
    std::array<double, 3> centre{0, 0, 0}; ///< m s-1, that centre
};

/// The velocity box's centre of every rank's nodes.
std::array<double, 3> velocity_centre(const Run& r) {
    const auto& st = r.s.state();
    const double inf = std::numeric_limits<double>::infinity();
    std::array<double, 3> lo{inf, inf, inf}, hi{-inf, -inf, -inf};
    for (auto row : st.rows)
        for (std::size_t d = 0; d < 3; ++d) {
            const double v = st.v[3 * static_cast<std::size_t>(row) + d];
            lo[d] = std::min(lo[d], v);
            hi[d] = std::max(hi[d], v);
        }
    if (r.par) {
        MPI_Allreduce(MPI_IN_PLACE, lo.data(), 3, MPI_DOUBLE, MPI_MIN, r.comm);
        MPI_Allreduce(MPI_IN_PLACE, hi.data(), 3, MPI_DOUBLE, MPI_MAX, r.comm);
    }
    std::array<double, 3> c{0, 0, 0};
    for (std::size_t d = 0; d < 3; ++d)
        if (lo[d] <= hi[d]) // no node anywhere: 0
            c[d] = 0.5 * (lo[d] + hi[d]);
    return c;
}

Closing fastest_closing(const Run& r) {
    const auto& st = r.s.state();
    const auto& walls = r.m.walls;
    std::vector<solver::WallPose> pose;
    for (const auto& w : walls)
        pose.push_back(solver::wall_pose(w, st.time));
    // [0]: relative to the velocity centre; [1 + k]: relative to wall k (MAXLOC pairs).
    struct Loc {
        double v;
        int i;
    };
    std::vector<Loc> best(1 + walls.size(), Loc{-1.0, 0});
    const auto c = velocity_centre(r);
    for (auto row : st.rows) {
        const auto i = static_cast<std::size_t>(row);
        const double* v = &st.v[3 * i];
        const double s = std::hypot(v[0] - c[0], v[1] - c[1], v[2] - c[2]);
        if (s > best[0].v)
            best[0] = {s, static_cast<int>(i)};
        const auto group = r.m.bodies.group[static_cast<std::size_t>(st.body[i])];
        for (std::size_t k = 0; k < walls.size(); ++k) {
            const auto* law = r.m.contact_between(group, walls[k].group);
            if (!law || !(law->stiffness > 0 && law->radius > 0) || st.time < walls[k].start_time)
                continue;
            const auto& p = pose[k];
            const double* x = &st.x[3 * i];
            const double q[3] = {x[0] - p.centre[0], x[1] - p.centre[1], x[2] - p.centre[2]};
            const double u[3] = {p.velocity[0] + p.omega[1] * q[2] - p.omega[2] * q[1],
                                 p.velocity[1] + p.omega[2] * q[0] - p.omega[0] * q[2],
                                 p.velocity[2] + p.omega[0] * q[1] - p.omega[1] * q[0]};
            const double sw = std::hypot(v[0] - u[0], v[1] - u[1], v[2] - u[2]);
            if (sw > best[1 + k].v)
                best[1 + k] = {sw, static_cast<int>(i)};
        }
    }
    if (r.par)
        MPI_Allreduce(MPI_IN_PLACE, best.data(), static_cast<int>(best.size()), MPI_DOUBLE_INT,
                      MPI_MAXLOC, r.comm);
    Closing out;
    out.centre = c;
    for (std::size_t k = 0; k < best.size(); ++k)
        if (best[k].v > out.speed) {
            out.speed = best[k].v;
            out.node = static_cast<std::size_t>(best[k].i);
            out.wall = static_cast<int>(k) - 1;
        }
    return out;
}

/// Contact at any speed, by a time-step limit from the velocities (the search does not sweep
/// along a step): fastest_closing's speed times dt must stay below the smallest contact radius.
/// Empty when it does (collective).
std::string too_fast(const Run& r) {
    double rc = std::numeric_limits<double>::infinity();
    bool surface = false; // the smallest reach is a surface law's (its mesh size h)
    for (const auto& p : r.m.contact)
        if (p.radius > 0 && p.radius < rc) {
            rc = p.radius;
            surface = p.law == model::ContactLaw::surface;
        }
    if (!std::isfinite(rc))
        return {};
    const char* reach = surface ? "contact reach (surface law: the mesh size)" : "contact radius";
    const char* sym = surface ? "h" : "R_c";
    const auto fc = fastest_closing(r);
    const double v = fc.speed;
    if (!(v * r.steps.dt >= rc))
        return {};
    const std::string against =
        fc.wall >= 0 ? fmt::format("relative to wall {} ('{}')", fc.wall,
                                   r.m.walls[static_cast<std::size_t>(fc.wall)].name)
                     : fmt::format("relative to the centre of the bodies' velocities ({:.4g}, "
                                   "{:.4g}, {:.4g}) m/s",
                                   fc.centre[0], fc.centre[1], fc.centre[2]);
    return fmt::format("node {} of body {} moves at {:.4g} m/s {}, {:.4g} m per step (dt = "
                       "{:.4g} s), not less than the smallest {} {} = {:.4g} m: "
                       "grains can pass through each other or a wall between two steps with no "
                       "contact seen. The contact search needs v dt < {}: dt below {:.4g} s "
                       "(solver.dt or dt_safety) or slower grains (--no-penetration-check runs "
                       "on)",
                       fc.node, r.s.state().body[fc.node], v, against, v * r.steps.dt, r.steps.dt,
                       reach, sym, rc, sym, rc / v);
}

class Guards final : public Action {
  public:
    explicit Guards(Run& r)
        : Action(observation_trigger(r.steps)) {
        reference(r);
        if (!r.opt.penetration_check)
            return;
        if (const auto why = too_fast(r); !why.empty()) { // stopped before the first step
            r.agreed = true; // every rank throws here (reduced values): no MPI_Abort
            throw NumericalError(
                fmt::format("{}: stopped before step {}: {}", r.opt.file, r.steps.first + 1, why));
        }
    }
    void run(Run& r, std::int64_t n) override {
        finite(r, n);
        bounded(r, n);
        if (r.opt.penetration_check) {
            if (const auto why = too_fast(r); !why.empty())
                stop_with_row(r, n, "too fast for contact",
                              fmt::format("{}: stopped at step {} (t = {:.6g} s): {}", r.opt.file,
                                          n, r.s.state().time, why));
            inside(r, n);
            beyond_wall(r, n);
        }
        balance(r, n);
    }

  private:
    double energy0_ = 0, balance0_ = 0, in_play_ = 0;
    bool warned_ = false; ///< solver.penetration "warn": the first breach was reported

    /// A node inside a grain or beyond a wall: stop (exit 3), or under solver.penetration "warn"
    /// (PeriDEM decks) say it once and go on. `o.inside_pairs` and `o.beyond_wall` are reduced
    /// over the ranks, so every rank takes the same branch.
    /// `on_stop` is what the stop adds (the flagged last frame); a warning has none.
    void breach(Run& r, std::int64_t n, const char* kind, const std::string& why,
                const char* on_stop) {
        if (!r.m.solver.penetration_warns)
            stop_with_row(r, n, kind, why + on_stop);
        warned_ = true;
        r.ctx.log.warn("{} (solver.penetration: warn, as PeriDEM decks run: the run goes on and "
                       "later ones are not reported)",
                       why);
    }

    void reference(Run& r);
    void finite(Run& r, std::int64_t n) const;
    void bounded(Run& r, std::int64_t n) const;
    void inside(Run& r, std::int64_t n);
    void beyond_wall(Run& r, std::int64_t n);
    void balance(Run& r, std::int64_t n);
};

/// Initial energy and balance: at t = 0 from the state, on a restart from the first observable
/// row (kept across restarts; NaN in a file from before pd-file 1.2: no balance check), the
/// energy in play as the largest over the rows so far.
void Guards::reference(Run& r) {
    if (r.steps.first == 0) {
        const auto o = r.s.observe();
        energy0_ = o.kinetic_energy + o.elastic_energy + o.contact_energy;
        balance0_ = solver::energy_balance(o);
        in_play_ = solver::energy_in_play(o);
        return;
    }
    auto series = store::read_observables(r.file);
    auto at = [&](const char* name, std::size_t row) {
        const auto it = series.find(name);
        return it != series.end() && row < it->second.value.size()
                   ? it->second.value[row]
                   : std::numeric_limits<double>::quiet_NaN();
    };
    const auto ke = series.find("kinetic_energy");
    const std::size_t rows = ke != series.end() ? ke->second.value.size() : 0;
    for (std::size_t row = 0; row < rows; ++row) {
        solver::Observables o;
        o.kinetic_energy = at("kinetic_energy", row);
        o.elastic_energy = at("elastic_energy", row);
        o.contact_energy = at("contact_energy", row);
        o.external_work = at("external_work", row);
        o.fracture_energy = at("fracture_energy", row);
        o.damping_dissipation = at("damping_dissipation", row);
        o.friction_dissipation = at("friction_dissipation", row);
        o.viscous_dissipation = at("viscous_dissipation", row);
        if (row == 0) {
            energy0_ = o.kinetic_energy + o.elastic_energy + o.contact_energy;
            balance0_ = solver::energy_balance(o);
        }
        in_play_ = std::max(in_play_, solver::energy_in_play(o));
    }
}

void Guards::finite(Run& r, std::int64_t n) const {
    const auto& o = r.last_obs;
    if (std::isfinite(o.kinetic_energy) && std::isfinite(o.elastic_energy) &&
        std::isfinite(o.contact_energy))
        return;
    failed_frame(r, n, "non-finite state");
    const auto i = r.s.first_nonfinite();
    throw NumericalError(
        fmt::format("{}: non-finite state at step {} (t = {:.6g} s){}; the last good frame "
                    "stays in the file. Lower dt (now {:.4g} s) or check the scene",
                    r.opt.file, n, r.s.state().time,
                    i >= 0 ? fmt::format(" at node {} of body {}", i,
                                         r.s.state().body[static_cast<std::size_t>(i)])
                           : std::string{},
                    r.steps.dt));
}

/// Blow-up: the mechanical energy far above what the system started with plus the work done on
/// it (it can only lose energy to damping and fracture).
void Guards::bounded(Run& r, std::int64_t n) const {
    const auto& o = r.last_obs;
    const double e = o.kinetic_energy + o.elastic_energy + o.contact_energy;
    if (!(e > 100.0 * (energy0_ + std::max(0.0, o.external_work)) + 1e-300))
        return;
    failed_frame(r, n, "blow-up");
    const auto& st = r.s.state();
    const auto [fast, vmax] = fastest(r);
    throw NumericalError(
        fmt::format("{}: blow-up at step {} (t = {:.6g} s): energy {:.4g} J against {:.4g} J "
                    "initial plus {:.4g} J of external work (fastest: node {} of body {}, "
                    "{:.3g} m/s); the last good frame stays in the file. Lower dt (now {:.4g} "
                    "s; "
                    "stability estimate {:.4g} s)",
                    r.opt.file, n, st.time, e, energy0_, o.external_work, fast, st.body[fast], vmax,
                    r.steps.dt, r.steps.est.limit));
}

/// Interpenetration: a node more than R_c + h/2 inside another grain.
void Guards::inside(Run& r, std::int64_t n) {
    const auto& o = r.last_obs;
    if (o.inside_pairs <= 0 || warned_)
        return;
    const auto pen = penetration_numbers(r); // collective
    const std::string where = o.inside_node >= 0
                                  ? fmt::format(" (node {} of body {} inside body {})",
                                                o.inside_node, o.inside_body, o.inside_of)
                                  : std::string{};
    // The surface law has no radius to raise: a node h/2 behind a boundary came through a
    // facet that could not hold the load (a sharp tip, a soft grain pressed hard) or through a
    // gap left by a boundary node that broke off (solver/surface_inside.cpp).
    const std::string advice =
        pen.surface
            ? "Contact failed: the surface law's pressure at h/2 depth (c h / 2) did not hold the "
              "load there. Refine the mesh (that pressure, kappa / 2 h, grows as 1 / h), slow the "
              "loading or impact, or give this pair the node law with a radius of 3 mesh sizes "
              "(contact \"law\": \"node\", \"radius_mesh_factor\": 3)"
            : "Contact failed: a node passed between the few nodes within R_c of it (README "
              "\"Tunnelling and the contact radius\": a stiffer K_n alone does not stop it). "
              "Give the grains' contact a radius of 3 mesh sizes (contact "
              "\"radius_mesh_factor\": 3) or slow the loading or impact";
    breach(r, n, "interpenetration",
           fmt::format("{}: grains interpenetrate at step {} (t = {:.6g} s): {} node pair(s) more "
                       "than {} inside another grain{}; {}. {}",
                       r.opt.file, n, r.s.state().time, o.inside_pairs,
                       pen.surface ? "h/2 behind a facet it came through, or in an intact cell a "
                                     "layer below the boundary,"
                                   : "the contact radius + h/2",
                       where, pen.numbers, advice),
           ". The state at this step is the last frame (flagged: /particles/nodes attribute "
           "failed_step), the frames before stay valid; --no-penetration-check runs on");
}

void Guards::beyond_wall(Run& r, std::int64_t n) {
    const auto& o = r.last_obs;
    if (o.beyond_wall <= 0 || warned_)
        return;
    // The advice follows the law of the walls' acting pairs (the same on every rank): the surface
    // law has no factor to raise, its stiffness follows the materials, the mesh and the speeds.
    // The pair of the node named and its wall decides where known; a pair switched off
    // (stiffness 0, e.g. a drum that does not act on its own protrusion) never does.
    auto node_pair = [&](std::int32_t body_group, std::int32_t wall_group) {
        bool node = false;
        for (const auto& p : r.m.contact) {
            const bool walls = p.group_a == wall_group || p.group_b == wall_group;
            const bool grain = body_group < 0 || p.group_a == body_group || p.group_b == body_group;
            if (walls && grain && p.stiffness > 0 && p.law == model::ContactLaw::node)
                node = true;
        }
        return node;
    };
    bool node_law = false;
    if (o.beyond_node >= 0 && o.beyond_wall_index >= 0 &&
        static_cast<std::size_t>(o.beyond_wall_index) < r.m.walls.size()) {
        const auto b =
            static_cast<std::size_t>(r.s.state().body[static_cast<std::size_t>(o.beyond_node)]);
        node_law = node_pair(r.m.bodies.group[b],
                             r.m.walls[static_cast<std::size_t>(o.beyond_wall_index)].group);
    } else {
        for (const auto& w : r.m.walls)
            node_law = node_law || node_pair(-1, w.group);
    }
    const char* advice =
        node_law ? "The wall contact is too soft for this impact (raise "
                   "contact.stiffness_factor, lower the speed)"
                 : "The surface law's pressure at h/2 behind the wall (kappa / 2 h) did not "
                   "hold this impact: refine the mesh (that pressure grows as 1 / h) or lower "
                   "the speed (the automatic stiffness follows the scene's speeds up to the "
                   "grains' wave speed)";
    breach(r, n, "node beyond a wall",
           fmt::format("{}: nodes pass through a rigid wall at step {} (t = {:.6g} s): {} "
                       "node(s) more than h/2 beyond a wall's surface{}. {}",
                       r.opt.file, n, r.s.state().time, o.beyond_wall,
                       o.beyond_node >= 0
                           ? fmt::format(" (node {} of body {}, wall {})", o.beyond_node,
                                         r.s.state().body[static_cast<std::size_t>(o.beyond_node)],
                                         o.beyond_wall_index)
                           : std::string{},
                       advice),
           "; the state at this step is the last frame (flagged), the frames before stay in "
           "the file (--no-penetration-check runs on)");
}

/// Velocity Verlet's full-step energy KE(v_n) + U(x_n) is not the energy it conserves: v_n
/// carries half a kick dt F_n / (2 m) that no work has paid for yet, so the balance can sit off
/// by sum |F_i|^2 dt^2 / (8 m_i) at any step (and by as much at its reference). Where nothing else
/// is in play, at a grain's first contact with a moving plate, that is a large share of the
/// energy (15 % at the first contact step, tolerance 5 %: tests/solve/test_energy_guard.py).
/// Collective (the callers' branch is on reduced values).
double kick_energy(const Run& r) {
    const auto& s = r.s.state();
    double e = 0;
    for (auto row : s.rows) {
        const auto i = static_cast<std::size_t>(row);
        if (!s.moving[i])
            continue;
        for (std::size_t d = 0; d < 3; ++d)
            if (!(s.fixed_dof[i] & (1u << d))) {
                const double F = s.f[3 * i + d] * s.vol[i];
                e += F * F / (8 * s.rho[i] * s.vol[i]);
            }
    }
    e *= r.steps.dt * r.steps.dt;
    if (r.par)
        MPI_Allreduce(MPI_IN_PLACE, &e, 1, MPI_DOUBLE, MPI_SUM, r.comm);
    return e;
}

/// Energy balance: energy created (an instability, even one that fracture then absorbs) or lost
/// without account shows up here long before 100x.
void Guards::balance(Run& r, std::int64_t n) {
    const auto& o = r.last_obs;
    in_play_ = std::max(in_play_, solver::energy_in_play(o));
    const double drift = solver::energy_balance(o) - balance0_;
    const double tol = r.opt.energy_tolerance;
    if (!(tol > 0 && std::isfinite(balance0_) && std::abs(drift) > tol * in_play_ && in_play_ > 0))
        return;
    // Within the integrator's own half kick (at this step and at the reference), as far as
    // contact can carry it: a first contact's is of its contact energy's order ((omega_c dt /
    // 2)^2 U_c, omega_c dt <= 2), while an unstable bond mode's would hide its own growth.
    if (std::abs(drift) <= tol * in_play_ + std::min(2 * kick_energy(r), o.contact_energy))
        return;
    r.obs.add(n, r.s.state().time, observable_row(o)); // the row that failed
    failed_frame(r, n, "energy balance");
    const auto [fast, vmax] = fastest(r);
    throw NumericalError(
        fmt::format("{}: energy balance broken at step {} (t = {:.6g} s): KE + elastic + "
                    "contact + dissipated - external work moved by {:+.4g} J, {:.3g} % of the "
                    "{:.4g} J in play (tolerance {:.3g} %, --energy-tolerance; broken bonds "
                    "{}; fastest: node {} of body {}, {:.3g} m/s). The time step (now {:.4g} "
                    "s, stability estimate {:.4g} s) is too large or the model is unstable; "
                    "the frames before stay in the file",
                    r.opt.file, n, r.s.state().time, drift, 100 * std::abs(drift) / in_play_,
                    in_play_, 100 * tol, o.broken_bonds, fast, r.s.state().body[fast], vmax,
                    r.steps.dt, r.steps.est.limit));
}

} // namespace

std::unique_ptr<Action> make_guards(Run& r) {
    return std::make_unique<Guards>(r);
}

} // namespace pd::pipeline::run
