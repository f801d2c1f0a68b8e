// SPDX-License-Identifier: MIT
// Contact of nodes with rigid walls (solver/walls.hpp); the walls' reactions; records the
// touching node-wall pairs for damping and friction.
#include "solver/forces.hpp"
#include "solver/stability.hpp"

#include <cmath>

namespace pd::solver {

namespace {
class RigidWalls final : public ForceTerm {
  public:
    void add(Forces& f) override {
        ScopedTimer t(f.timers, f.t_walls);
        f.walls->update(f.s);
        f.walls->add_forces(f.s, f.wall_load, f.records ? &f.wall_records : nullptr, f.dt);
        f.contact_count += f.wall_load.touching;
        f.contact_energy += f.wall_load.energy;
    }
    void limit_dt(const Forces& f, StableDt& dt) const override {
        if (!std::isfinite(dt.contact))
            dt.contact = critical_dt(contact_lambda_bound(f.m, f.s));
    }
    void observe(const Forces& f, Observables& o) const override {
        o.beyond_wall = f.wall_load.beyond;
        o.beyond_node = f.wall_load.beyond_node;
        o.beyond_wall_index = f.wall_load.beyond_wall;
    }
    std::vector<const char*> checkpointed() const override { return {"external_work", "power"}; }
};
} // namespace

std::unique_ptr<ForceTerm> make_rigid_walls(Forces& f) {
    // Not active (no wall with a contact law): the walls' loads stay the zeros they were sized
    // with (damping and friction add to them only through wall records, which stay empty).
    return f.walls->active() ? std::make_unique<RigidWalls>() : nullptr;
}

} // namespace pd::solver
