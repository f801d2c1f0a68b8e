// SPDX-License-Identifier: MIT
#include "pipeline/run/schedule.hpp"

#include "pipeline/full_disk.hpp"
#include "store/frames.hpp"

#include <map>
#include <span>

namespace pd::pipeline::run {

#define PD_ACTION(name) std::unique_ptr<Action> make_##name(Run& r);
#include "pipeline/run/actions.def"
#undef PD_ACTION

Schedule::Schedule(Run& r) {
    r.schedule = this;
#define PD_ACTION(name)                                                                            \
    if (auto a = make_##name(r))                                                                   \
        actions_.push_back(std::move(a));
#include "pipeline/run/actions.def"
#undef PD_ACTION
    const double now = wall_seconds();
    for (auto& a : actions_)
        a->trigger().start(now);
}

bool Schedule::needs_energies(std::int64_t n) const {
    for (const auto& a : actions_)
        if (a->needs_energies() && a->trigger()(n))
            return true;
    return false;
}

bool Schedule::after_step(Run& r, std::int64_t n) {
    for (auto& a : actions_) {
        if (!a->trigger()(n))
            continue;
        a->run(r, n);
        a->trigger().fired(wall_seconds());
        if (r.stop)
            return false;
    }
    return true;
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

double busy_seconds(Timers& timers) {
    double busy = 0;
    for (const char* name :
         {"pd::solver::bond_forces", "pd::solver::contact_forces", "pd::solver::contact_search",
          "pd::solver::wall_contact", "pd::solver::integrate", "pd::solver::damping_friction"})
        busy += timers.total(timers.id(name));
    return busy;
}

void ensure_room(const Run& r, bool frame, bool checkpoint) {
    if (!r.par)
        return;
    std::uint64_t bytes = r.obs.flush_bytes();
    if (frame)
        bytes += r.frames.frame_bytes();
    if (checkpoint) // displacement, velocity, force density (3 per node each), bond_alive
        bytes += 8 * 9 * static_cast<std::uint64_t>(r.m.nodes.num()) +
                 static_cast<std::uint64_t>(r.m.bonds.num());
    pipeline::ensure_room(r.opt.file, bytes,
                          fmt::format("the {} of step {}",
                                      frame && checkpoint ? "frame and checkpoint"
                                      : frame             ? "frame"
                                                          : "checkpoint",
                                      r.s.state().step),
                          r.comm, r.ctx.rank);
}

void write_frame(Run& r) {
    thread_local std::vector<double> damage_z, fragment, broken;
    // Only the requested fields are computed.
    const auto& s = r.s;
    const auto& st = s.state();
    std::map<std::string, std::span<const double>> data;
    data["position"] = st.x;
    for (const auto& name : r.frames.fields()) {
        if (name == "velocity")
            data[name] = st.v;
        else if (name == "displacement")
            data[name] = st.u;
        else if (name == "force") {
            s.nodal_force(r.force);
            data[name] = r.force;
        } else if (name == "damage") {
            s.damage(r.damage);
            data[name] = r.damage;
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
    r.frames.write(st.step, st.time, data);
}

} // namespace pd::pipeline::run
