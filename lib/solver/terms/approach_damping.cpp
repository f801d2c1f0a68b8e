// SPDX-License-Identifier: MIT
// PeriDEM 0.2's particle damping (its DEMModel::computeContactForces after the node contact),
// for decks imported with `pd-pack --from-peridem --parity peridem` (issue 28 item 6): PeriDEM
// damps grains while they approach, from a gap of 1.01 R_c on, where pdgrain's own damping
// (contact_damping.cpp) acts while a contact unloads. With c_i grain i's centre node (the node
// nearest its placement centre, as PeriDEM's reference particle picks it), R_i its bounding
// radius and m_i = rho_i pi R_i^2 (2D, per unit thickness):
// - two grains with |x_cj - x_ci| < R_i + R_j + 1.01 R_c: beta = A sqrt(R_c m_eq), m_eq =
//   2 m_i m_j / (m_i + m_j) (PeriDEM's util::equivalentMass: m for equal grains, not the reduced
//   mass), n = (x_cj - x_ci) / |.|, and every node of i gets the force density
//   beta min(0, (v_cj - v_ci) . n) n / (pi R_i^2);
// - a grain and every node k of a meshed wall within R_c of one of its nodes: the same with
//   m_eq = m_i, n from x_ci to x_k and v_k - v_ci.
// A = beta_n sqrt(kappa) is the pair's `approach` (model::ContactPair). As in PeriDEM the two
// grains' forces are not equal and opposite (each is scaled by its own pi R^2 against its own
// area) and the walls feel none. The pair loop is over all grains (O(P^2), as PeriDEM's): this
// term is for PeriDEM's decks. Dissipation: minus the power of these forces on the grains' nodes.
#include "solver/forces.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace pd::solver {

namespace {

class ApproachDamping final : public ForceTerm {
  public:
    explicit ApproachDamping(const Forces& f) {
        const auto& B = f.m.bodies;
        centre_.assign(B.num(), -1);
        for (std::size_t b = 0; b < B.num(); ++b) {
            if (B.kind[b] != model::BodyKind::particle)
                continue;
            grains_.push_back(b);
            // PeriDEM's RefParticle: the first node strictly nearest the centre, from a start
            // of the bounding radius.
            double best = B.bounding_radius[b];
            for (auto i = B.begin(b); i < B.end(b); ++i) {
                double r2 = 0;
                for (std::size_t d = 0; d < 3; ++d)
                    r2 += std::pow(B.center[3 * b + d] - f.m.nodes.x0[3 * std::size_t(i) + d], 2);
                if (std::sqrt(r2) < best) {
                    best = std::sqrt(r2);
                    centre_[b] = i;
                }
            }
            if (centre_[b] < 0)
                centre_[b] = B.begin(b);
        }
    }

    void add(Forces& f) override {
        ScopedTimer t(f.timers, f.t_damping);
        centres(f);
        for (auto b : grains_) {
            if (f.m.bodies.fixed[b] || !f.dom->owns(f.m.bodies.begin(b)))
                continue; // an obstacle does not move (whole grains per rank: checked)
            double fd[3] = {0, 0, 0};
            grain_pairs(f, b, fd);
            wall_nodes(f, b, fd);
            if (fd[0] != 0 || fd[1] != 0 || fd[2] != 0)
                apply(f, b, fd);
        }
    }
    std::vector<const char*> checkpointed() const override { return {"damping", "damping_rate"}; }

  private:
    /// x and v of every grain's centre node, over the ranks (its owner adds them, others 0).
    void centres(const Forces& f) {
        const auto& s = f.s;
        c_.assign(6 * f.m.bodies.num(), 0.0);
        for (auto b : grains_) {
            const auto i = centre_[b];
            if (!f.dom->owns(i))
                continue;
            for (std::size_t d = 0; d < 3; ++d) {
                c_[6 * b + d] = s.x[3 * std::size_t(i) + d];
                c_[6 * b + 3 + d] = s.v[3 * std::size_t(i) + d];
            }
        }
        if (f.dom->distributed())
            f.dom->sum(c_);
    }
    double mass(const Forces& f, std::size_t b) const {
        const double r = f.m.bodies.bounding_radius[b];
        return f.m.materials[std::size_t(f.m.bodies.material[b])].density * std::numbers::pi * r *
               r;
    }
    /// Adds beta min(0, (v - v_ci) . n) n / (pi R_i^2), n the unit vector from x_ci to x.
    void push(const Forces& f, std::size_t b, double beta, const double* x, const double* v,
              double* fd) const {
        const double* xc = &c_[6 * b];
        const double* vc = &c_[6 * b + 3];
        double n[3] = {x[0] - xc[0], x[1] - xc[1], x[2] - xc[2]};
        const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (!(len > 0))
            return;
        double vn = 0;
        for (int d = 0; d < 3; ++d) {
            n[d] /= len;
            vn += (v[d] - vc[d]) * n[d];
        }
        if (vn >= 0)
            return; // separating: no damping
        const double r = f.m.bodies.bounding_radius[b];
        const double k = beta * vn / (std::numbers::pi * r * r);
        for (int d = 0; d < 3; ++d)
            fd[d] += k * n[d];
    }
    /// The law between bodies a and b if it damps (PeriDEM's approach damping, some stiffness).
    static const model::ContactPair* damped(const Forces& f, std::size_t a, std::size_t b) {
        const auto* law = f.m.contact_between(f.m.bodies.group[a], f.m.bodies.group[b]);
        return law && law->approach > 0 && law->stiffness > 0 ? law : nullptr;
    }
    static double dist(const double* p, const double* q) {
        return std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                         (p[2] - q[2]) * (p[2] - q[2]));
    }
    void grain_pairs(const Forces& f, std::size_t b, double* fd) const {
        const auto& B = f.m.bodies;
        for (auto o : grains_) {
            if (o == b)
                continue;
            const auto* law = damped(f, b, o);
            if (!law || !(dist(&c_[6 * o], &c_[6 * b]) <
                          B.bounding_radius[b] + B.bounding_radius[o] + 1.01 * law->radius))
                continue;
            const double mi = mass(f, b), mj = mass(f, o);
            const double beta = law->approach * std::sqrt(law->radius * 2 * mi * mj / (mi + mj));
            push(f, b, beta, &c_[6 * o], &c_[6 * o + 3], fd);
        }
    }
    /// The meshed-wall nodes within R_c of a node of grain b, each once.
    void wall_nodes(const Forces& f, std::size_t b, double* fd) {
        const auto& B = f.m.bodies;
        const auto& s = f.s;
        near_.clear();
        for (auto i = B.begin(b); i < B.end(b); ++i) {
            const auto [k0, k1] = f.contact->candidates(i);
            for (auto p = k0; p != k1; ++p) {
                const auto k = std::size_t(*p);
                const auto bk = std::size_t(s.body[k]);
                if (B.kind[bk] != model::BodyKind::wall)
                    continue;
                const auto* law = damped(f, b, bk);
                if (law && dist(&s.x[3 * k], &s.x[3 * std::size_t(i)]) < law->radius)
                    near_.push_back(*p);
            }
        }
        std::sort(near_.begin(), near_.end());
        near_.erase(std::unique(near_.begin(), near_.end()), near_.end());
        for (auto k : near_) {
            const auto kk = std::size_t(k);
            const auto* law = f.m.contact_between(B.group[b], B.group[std::size_t(s.body[kk])]);
            const double beta = law->approach * std::sqrt(law->radius * mass(f, b));
            push(f, b, beta, &s.x[3 * kk], &s.v[3 * kk], fd);
        }
    }
    /// fd on every node of grain b, and its power into the dissipation rate.
    static void apply(Forces& f, std::size_t b, const double* fd) {
        auto& s = f.s;
        double power = 0;
        for (auto i = f.m.bodies.begin(b); i < f.m.bodies.end(b); ++i) {
            const auto ii = std::size_t(i);
            for (std::size_t d = 0; d < 3; ++d) {
                s.f[3 * ii + d] += fd[d];
                power += s.vol[ii] * fd[d] * s.v[3 * ii + d];
            }
        }
        f.diss.damping_rate -= power;
    }

    std::vector<std::size_t> grains_; ///< the bodies of kind particle
    std::vector<index_t> centre_;     ///< per body: its centre node (-1: a wall)
    std::vector<double> c_;           ///< 6 per body: x, v of the centre node
    std::vector<index_t> near_;
};

} // namespace

std::unique_ptr<ForceTerm> make_approach_damping(Forces& f) {
    // Only for contact laws with PeriDEM's particle damping (pd-pack refuses it outside the 2D
    // node law); none in a scene of pdgrain's own.
    return f.approach ? std::make_unique<ApproachDamping>(f) : nullptr;
}

} // namespace pd::solver
