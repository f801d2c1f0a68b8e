// SPDX-License-Identifier: MIT
// Contact reactions of meshed walls: the bodies that are fixed, or whose every node is driven by
// a displacement condition (a moving plate, a rotating container). Each records the force it
// receives from contact (normal contact, hysteretic damping, friction; node-node and from rigid
// walls) and its moment about the body's current centroid, as rigid walls do (solver/walls.hpp).
// The contact share of a node's force is what the contact stages add to s.f: a snapshot before
// them, the difference after.
#pragma once

#include "model/model.hpp"
#include "solver/domain.hpp"
#include "solver/state.hpp"

#include <cstdint>
#include <vector>

namespace pd::solver {

class BodyReactions {
  public:
    explicit BodyReactions(const model::Model& m);

    /// The bodies that record a reaction, ascending.
    const std::vector<std::int32_t>& bodies() const { return bodies_; }
    bool empty() const { return bodies_.empty(); }
    /// Takes this rank's rows (after a change of ownership).
    void set_rows(const State& s);
    /// Before the contact stages of a force evaluation: remembers the rows' forces and clears
    /// the reactions.
    void before(const State& s);
    /// After them: adds the differences (this rank's share).
    void after(const State& s);
    bool records(std::int32_t b) const { return index_[static_cast<std::size_t>(b)] >= 0; }
    /// The hysteretic damping share F (N) of body b's contact with another grain, between
    /// before() and after(): it acts through `point` (the other grain's centre of mass, as for
    /// rigid walls). The solver spreads it over a driven body in proportion to mass (s.f, so
    /// after() already counts it, about `centroid`): only the moment is corrected. A fixed body
    /// does not move and s.f does not carry it (`fixed`): force and moment are added.
    void add_damping(std::int32_t b, const double* F, const double* point, const double* centroid,
                     bool fixed);
    /// This rank's loads of the last evaluation: 10 per body (force, sum x cross force, sum m x,
    /// sum m), the values result() reduces; the solver sums them over an observation interval.
    const std::vector<double>& load() const { return load_; }
    /// Force (3 per body, N) and moment about the centroid (3 per body, N m), summed over the
    /// ranks, from `load` (a sum of load() over `steps` evaluations: their average) or, when
    /// null, from the last evaluation's. Collective.
    void result(const Domain& dom, std::vector<double>& force, std::vector<double>& moment,
                const std::vector<double>* load = nullptr, std::int64_t steps = 1) const;

  private:
    std::vector<std::int32_t> bodies_;
    std::vector<std::int32_t> index_; ///< body -> position in bodies_, or -1
    std::vector<index_t> rows_;       ///< this rank's rows of those bodies
    std::vector<double> f0_;          ///< 3 per row
    /// 10 per body: force, sum x cross force, sum m x, sum m (this rank's rows).
    std::vector<double> load_;
};

} // namespace pd::solver
