// SPDX-License-Identifier: MIT
// Node-pair contact between grains (solver/contact.hpp): the contact list's rebuild when nodes
// moved half the skin, then the normal forces; records the touching pairs for damping and
// friction.
#include "solver/forces.hpp"
#include "solver/stability.hpp"

#include <cmath>

namespace pd::solver {

namespace {
class NodeContact final : public ForceTerm {
  public:
    void add(Forces& f) override {
        {
            ScopedTimer t(f.timers, f.t_search);
            if (f.contact->update(f.s, *f.dom, &f.b, f.broken_total) && f.dom->distributed())
                set_ghosts(f);
            f.diss.fracture += f.contact->take_released(); // facets torn at the rebuild
        }
        ScopedTimer t(f.timers, f.t_contact);
        double energy = 0;
        f.contact_count +=
            f.contact->add_forces(f.s, energy, f.records ? &f.pair_records : nullptr);
        f.contact_energy += energy;
    }
    void limit_dt(const Forces& f, StableDt& dt) const override {
        // The Gershgorin bound of the densest contact that can form (node pairs and walls alike).
        if (!std::isfinite(dt.contact))
            dt.contact = critical_dt(contact_lambda_bound(f.m, f.s));
    }
    void observe(const Forces& f, Observables& o) const override {
        // The law's count (the last evaluation) and, under the surface law, the nodes inside
        // another body's intact material found now (surface_inside.cpp).
        auto pen = f.contact->penetration();
        const auto mat = f.contact->inside_material(f.s);
        if (pen.node < 0 || (mat.node >= 0 && mat.node < pen.node)) {
            pen.node = mat.node;
            pen.body = mat.body;
            pen.inside = mat.inside;
        }
        o.inside_pairs = pen.count + mat.count;
        o.inside_node = pen.node;
        o.inside_body = pen.body;
        o.inside_of = pen.inside;
    }
};
} // namespace

std::unique_ptr<ForceTerm> make_node_contact(Forces& f) {
    // Not active (one body, or no contact law with a stiffness): no pair ever touches, the
    // contact energy and count stay 0 and no pair is recorded for damping or friction.
    return f.contact->active() ? std::make_unique<NodeContact>() : nullptr;
}

} // namespace pd::solver
