// SPDX-License-Identifier: MIT
#include "solver/walls.hpp"

#include "model/functions.hpp"
#include "model/wall_mesh.hpp"
#include "solver/surface_penalty.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pd::solver {

namespace {

using V3 = std::array<double, 3>;

/// Rotation of v by the rotation vector theta (Rodrigues).
V3 rotate(const V3& v, const V3& theta) {
    const double a = std::sqrt(theta[0] * theta[0] + theta[1] * theta[1] + theta[2] * theta[2]);
    if (a == 0)
        return v;
    const V3 k{theta[0] / a, theta[1] / a, theta[2] / a};
    const double c = std::cos(a), s = std::sin(a);
    const double kv = k[0] * v[0] + k[1] * v[1] + k[2] * v[2];
    const V3 kxv{k[1] * v[2] - k[2] * v[1], k[2] * v[0] - k[0] * v[2], k[0] * v[1] - k[1] * v[0]};
    V3 r;
    for (int d = 0; d < 3; ++d)
        r[d] = v[d] * c + kxv[d] * s + k[d] * kv * (1 - c);
    return r;
}

/// Signed distance of a mesh wall: x taken into the wall's reference frame by the inverse pose,
/// the normal back by the pose; +infinity (n = 0) when no cell lies within rmax.
double mesh_distance(const model::Wall& w, const WallPose& p, const double* x, double n[3],
                     double rmax) {
    const V3 rel = rotate({x[0] - p.centre[0], x[1] - p.centre[1], x[2] - p.centre[2]},
                          {-p.theta[0], -p.theta[1], -p.theta[2]});
    const double X[3] = {w.centre[0] + rel[0], w.centre[1] + rel[1], w.centre[2] + rel[2]};
    double d = HUGE_VAL, nr[3] = {0, 0, 0};
    if (!w.mesh->closest(X, rmax, d, nr)) {
        n[0] = n[1] = n[2] = 0;
        return HUGE_VAL;
    }
    const V3 nw = rotate({nr[0], nr[1], nr[2]}, p.theta);
    for (int k = 0; k < 3; ++k)
        n[k] = nw[k];
    return d;
}

/// Signed distance of x from the wall (positive on the free side) and the unit normal into
/// the free side at the closest point (mesh walls: searched within rmax).
double distance(const model::Wall& w, const WallPose& p, const double* x, double n[3],
                double rmax) {
    if (w.shape == model::WallShape::mesh)
        return mesh_distance(w, p, x, n, rmax);
    if (w.shape == model::WallShape::plane) {
        double d = 0;
        for (int k = 0; k < 3; ++k) {
            n[k] = p.normal[k];
            d += (x[k] - p.point[k]) * n[k];
        }
        return d;
    }
    double r[3], rr = 0;
    for (int k = 0; k < 3; ++k) {
        r[k] = x[k] - p.point[k];
        rr += r[k] * r[k];
    }
    rr = std::sqrt(rr);
    const double sgn = w.shape == model::WallShape::circle_inside ? -1.0 : 1.0;
    for (int k = 0; k < 3; ++k)
        n[k] = rr > 0 ? sgn * r[k] / rr : 0.0;
    return w.shape == model::WallShape::circle_inside ? w.radius - rr : rr - w.radius;
}

} // namespace

double wall_distance(const model::Wall& w, const WallPose& p, const double* x, double n[3],
                     double rmax) {
    return distance(w, p, x, n, rmax);
}

WallPose wall_pose(const model::Wall& w, double t) {
    WallPose p;
    double rate = 0;
    const double T = model::wall_time(w, t, &rate);
    V3 theta{w.angular_velocity[0] * T, w.angular_velocity[1] * T, w.angular_velocity[2] * T};
    for (int d = 0; d < 3; ++d)
        p.centre[d] = w.centre[d] + w.velocity[d] * T;
    V3 rel{w.point[0] - w.centre[0], w.point[1] - w.centre[1], w.point[2] - w.centre[2]};
    rel = rotate(rel, theta);
    for (int d = 0; d < 3; ++d)
        p.point[d] = p.centre[d] + rel[d];
    p.normal = rotate(w.normal, theta);
    p.theta = theta;
    for (int d = 0; d < 3; ++d) {
        p.velocity[d] = w.velocity[d] * rate;
        p.omega[d] = w.angular_velocity[d] * rate;
    }
    return p;
}

WallContact::WallContact(const model::Model& m, double skin)
    : m_(m)
    , walls_(m.walls)
    , skin_(skin) {
    for (auto g : m.bodies.group)
        ngroups_ = std::max(ngroups_, g + 1);
    law_.assign(static_cast<std::size_t>(ngroups_) * walls_.size(), -1);
    for (std::size_t w = 0; w < walls_.size(); ++w)
        for (int g = 0; g < ngroups_; ++g)
            for (std::size_t k = 0; k < m.contact.size(); ++k) {
                const auto& c = m.contact[k];
                if (((c.group_a == g && c.group_b == walls_[w].group) ||
                     (c.group_b == g && c.group_a == walls_[w].group)) &&
                    c.stiffness > 0 && c.radius > 0) {
                    law_[static_cast<std::size_t>(g) * walls_.size() + w] =
                        static_cast<std::int32_t>(k);
                    rc_max_ = std::max(rc_max_, c.radius);
                }
            }
    active_ = std::any_of(law_.begin(), law_.end(), [](auto k) { return k >= 0; });
    reach_ = rc_max_ + skin_;
    for (const auto& w : walls_)
        for (int d = 0; d < 3; ++d)
            moving_ = moving_ || w.velocity[static_cast<std::size_t>(d)] != 0 ||
                      w.angular_velocity[static_cast<std::size_t>(d)] != 0 || w.start_time > 0;
}

bool WallContact::update(const State& s) {
    if (!active_)
        return false;
    if (built_) {
        // Bound on how far any wall surface point near the grains moved since the build.
        double wall_move = 0;
        for (const auto& w : walls_) {
            double rate = 0;
            const double dT =
                std::abs(model::wall_time(w, s.time, &rate) - model::wall_time(w, t_build_, &rate));
            const double v =
                std::sqrt(w.velocity[0] * w.velocity[0] + w.velocity[1] * w.velocity[1] +
                          w.velocity[2] * w.velocity[2]);
            const double om = std::sqrt(w.angular_velocity[0] * w.angular_velocity[0] +
                                        w.angular_velocity[1] * w.angular_velocity[1] +
                                        w.angular_velocity[2] * w.angular_velocity[2]);
            // (the rotation centre itself may have moved v dT away from the nodes since)
            wall_move = std::max(wall_move, (v + om * (extent_ + v * dT)) * dT);
        }
        if (!moved_farther_than(s, x_build_, 0.5 * skin_ - wall_move))
            return false;
    }
    rebuild(s);
    return true;
}

void WallContact::rebuild(const State& s) {
    ++rebuilds_;
    built_ = true;
    x_build_ = s.x;
    t_build_ = s.time;
    nodes_.clear();
    wall_of_.clear();
    offsets_.assign(1, 0);
    extent_ = 0;
    std::vector<WallPose> pose;
    for (const auto& w : walls_)
        pose.push_back(wall_pose(w, s.time));
    const double reach = rc_max_ + skin_;
    // No node is skipped by its depth inside its grain: every moving node is tested against
    // every wall (one distance each), so a grain pressed deep into a wall keeps meeting it.
    for (const auto row : s.rows) {
        const auto i = static_cast<std::size_t>(row);
        if (!s.moving[i])
            continue;
        const auto g =
            static_cast<std::size_t>(m_.bodies.group[static_cast<std::size_t>(s.body[i])]);
        bool any = false;
        for (std::size_t w = 0; w < walls_.size(); ++w) {
            if (law_[g * walls_.size() + w] < 0)
                continue;
            double n[3];
            const double d = distance(walls_[w], pose[w], &s.x[3 * i], n, reach_);
            if (d < reach) {
                wall_of_.push_back(static_cast<std::int32_t>(w));
                any = true;
            }
            // Every moving node, candidate or not: a wall point that may come within reach of
            // any node lies within |x_i - c| + reach of the rotation centre c, so it moves at
            // most omega (|x_i - c| + reach) per unit of the time function.
            double r2 = 0;
            for (int k = 0; k < 3; ++k)
                r2 += (s.x[3 * i + k] - pose[w].centre[k]) * (s.x[3 * i + k] - pose[w].centre[k]);
            extent_ = std::max(extent_, std::sqrt(r2) + reach);
        }
        if (any) {
            nodes_.push_back(static_cast<index_t>(i));
            offsets_.push_back(static_cast<std::int64_t>(wall_of_.size()));
        }
    }
}

namespace {
/// A node at signed distance d from a wall (d < offset: touching): its contact energy (J) and
/// the normal force density on it (N m-3). Node law: a mirror node of the same volume,
/// Kn (R_c - d) V (the products in the order they always had: node-law runs stay bitwise the
/// same); surface law: the penalty of surface_penalty.hpp at depth -d, onset over 0.01 h.
Penalty wall_penalty(const model::ContactPair& law, double d, double vol) {
    if (law.law == model::ContactLaw::surface) {
        const auto p = surface_penalty(law.stiffness, -d, onset_share * law.radius);
        return {p.energy * vol, p.force};
    }
    const double g = law.radius - d;
    return {0.5 * law.stiffness * g * g * vol * vol, law.stiffness * g * vol};
}

/// Every wall's pose at time t, and whether it is there.
void poses(const std::vector<model::Wall>& walls, double t, std::vector<WallPose>& pose,
           std::vector<std::uint8_t>& present) {
    pose.clear();
    present.clear();
    for (const auto& w : walls) {
        pose.push_back(wall_pose(w, t));
        present.push_back(model::wall_present(w, t) ? 1 : 0);
    }
}

/// An empty load of nw walls.
void clear(WallLoad& load, std::size_t nw) {
    load.force.assign(3 * nw, 0.0);
    load.moment.assign(3 * nw, 0.0);
    load.work = 0;
    load.touching = 0;
    load.energy = 0;
    load.beyond = 0;
    load.beyond_node = -1;
    load.beyond_wall = -1;
}

/// Adds the force F a wall receives at r from its centre to its force and moment (fm: 6 per
/// wall).
void add_reaction(double* fm, const double* F, const double* r) {
    fm[0] += F[0];
    fm[1] += F[1];
    fm[2] += F[2];
    fm[3] += r[1] * F[2] - r[2] * F[1];
    fm[4] += r[2] * F[0] - r[0] * F[2];
    fm[5] += r[0] * F[1] - r[1] * F[0];
}

/// The walls' forces and moments (fm, 6 per wall) into the load; the records sorted.
void finish(WallLoad& load, const std::vector<double>& fm, std::vector<BodyWallForce>& records,
            std::vector<BodyWallForce>* normal) {
    const std::size_t nw = fm.size() / 6;
    for (std::size_t w = 0; w < nw; ++w)
        for (int q = 0; q < 3; ++q) {
            load.force[3 * w + static_cast<std::size_t>(q)] =
                fm[6 * w + static_cast<std::size_t>(q)];
            load.moment[3 * w + static_cast<std::size_t>(q)] =
                fm[6 * w + 3 + static_cast<std::size_t>(q)];
        }
    if (normal) {
        // Deterministic order whatever the thread schedule (bitwise restarts).
        std::sort(records.begin(), records.end(), [](const auto& a, const auto& b) {
            return a.node != b.node ? a.node < b.node : a.wall < b.wall;
        });
        *normal = std::move(records);
    }
}
} // namespace

double WallContact::first_contact(const State& s, const std::vector<WallPose>& pose,
                                  const std::vector<WallPose>& prev,
                                  const std::vector<std::uint8_t>& present,
                                  const std::vector<std::uint8_t>& present_prev, double dt) const {
    const std::size_t nw = walls_.size();
    double corr = 0;
    for (std::size_t a = 0; a < nodes_.size(); ++a) {
        const auto i = static_cast<std::size_t>(nodes_[a]);
        const double* x = &s.x[3 * i];
        const auto g =
            static_cast<std::size_t>(m_.bodies.group[static_cast<std::size_t>(s.body[i])]);
        for (auto k = offsets_[a]; k < offsets_[a + 1]; ++k) {
            const auto w = static_cast<std::size_t>(wall_of_[static_cast<std::size_t>(k)]);
            if (!present[w])
                continue;
            const auto& law = m_.contact[static_cast<std::size_t>(law_[g * nw + w])];
            const double r0 = law.offset();
            double n[3], np[3];
            const double d = distance(walls_[w], pose[w], x, n, reach_);
            if (d >= r0)
                continue; // not touching
            // Where the wall was a step before (the node where it is now): beyond the onset the
            // force is linear in the depth and the trapezoid exact; within it (surface law, the
            // first 0.01 h) the force is quadratic and the trapezoid over-counts by up to 1/6 of
            // the step's work, which the first dozen steps of a slow platen made 7 % of the
            // energy in play.
            const double onset =
                law.law == model::ContactLaw::surface ? onset_share * law.radius : 0.0;
            const double dp = present_prev[w] ? distance(walls_[w], prev[w], x, np, reach_) : r0;
            if (dp < r0 - onset)
                continue; // touching already with the wall a step before, beyond the onset
            const auto pen = wall_penalty(law, d, s.vol[i]);
            const auto before = dp < r0 ? wall_penalty(law, dp, s.vol[i]) : Penalty{0.0, 0.0};
            const double u = pen.energy - before.energy;            // J
            const double F = (pen.force + before.force) * s.vol[i]; // N on the node, twice
            const auto& p = pose[w];
            const double r[3] = {x[0] - p.centre[0], x[1] - p.centre[1], x[2] - p.centre[2]};
            const double vw[3] = {p.velocity[0] + p.omega[1] * r[2] - p.omega[2] * r[1],
                                  p.velocity[1] + p.omega[2] * r[0] - p.omega[0] * r[2],
                                  p.velocity[2] + p.omega[0] * r[1] - p.omega[1] * r[0]};
            corr += u - 0.5 * dt * F * (n[0] * vw[0] + n[1] * vw[1] + n[2] * vw[2]);
        }
    }
    return corr;
}

void WallContact::add_forces(State& s, WallLoad& load, std::vector<BodyWallForce>* normal,
                             double dt) const {
    const std::size_t nw = walls_.size();
    clear(load, nw);
    if (!active_ || nodes_.empty())
        return;
    auto& pose = pose_; // (members: nothing allocated per step)
    auto& present = present_;
    poses(walls_, s.time, pose, present);
    const auto nn = static_cast<std::int64_t>(nodes_.size());
    auto& fm = fm_;
    fm.assign(6 * nw, 0.0); // force then moment, per wall
    double* fmp = fm.data();
    const std::size_t len = fm.size();
    std::int64_t touching = 0, beyond = 0;
    double energy = 0;
    std::vector<BodyWallForce> records;
    if (threaded(nn)) { // (no one-thread region on every step: see threaded())
#pragma omp parallel reduction(+ : touching, energy, beyond, fmp[:len])
        add_nodes(s, {pose, present, load, normal, records}, touching, energy, beyond, fmp);
    } else {
        add_nodes(s, {pose, present, load, normal, records}, touching, energy, beyond, fmp);
    }
    load.touching = touching;
    load.energy = energy;
    load.beyond = beyond;
    finish(load, fm, records, normal);
    if (dt > 0 && moving_) {
        poses(walls_, s.time - dt, pose_prev_, present_prev_);
        load.work = first_contact(s, pose, pose_prev_, present, present_prev_, dt);
    }
}

// The candidate nodes on the calling thread or, inside add_forces' region, this thread's share
// of them (an orphaned `omp for`); the sums and fm are the thread's own.
void WallContact::add_nodes(State& s, const Step& st, std::int64_t& touching, double& energy,
                            std::int64_t& beyond, double* fmp) const {
    const std::size_t nw = walls_.size();
    const auto nn = static_cast<std::int64_t>(nodes_.size());
    const auto& pose = st.pose;
    const auto& present = st.present;
    const auto normal = st.normal;
    auto& load = st.load;
    std::vector<BodyWallForce> mine;
    std::int64_t first = -1;
    std::int32_t first_wall = -1;
#pragma omp for schedule(static) nowait
    for (std::int64_t a = 0; a < nn; ++a) {
        const auto i = static_cast<std::size_t>(nodes_[static_cast<std::size_t>(a)]);
        const double* x = &s.x[3 * i];
        const auto g =
            static_cast<std::size_t>(m_.bodies.group[static_cast<std::size_t>(s.body[i])]);
        for (auto k = offsets_[static_cast<std::size_t>(a)];
             k < offsets_[static_cast<std::size_t>(a) + 1]; ++k) {
            const auto w = static_cast<std::size_t>(wall_of_[static_cast<std::size_t>(k)]);
            if (!present[w])
                continue;
            const auto& law = m_.contact[static_cast<std::size_t>(law_[g * nw + w])];
            double n[3];
            const double d = distance(walls_[w], pose[w], x, n, reach_);
            const double r0 = law.offset(); // R_c (node law) or 0 (surface law)
            if (d >= r0)
                continue;
            if (d < -0.5 * m_.bodies.mesh_size[static_cast<std::size_t>(s.body[i])]) {
                ++beyond; // more than h/2 through the wall
                if (first < 0) {
                    first = static_cast<std::int64_t>(i);
                    first_wall = static_cast<std::int32_t>(w);
                }
            }
            // density: node law Kn (R_c - d) V_i (a mirror node of the same volume); surface law
            // U'(-d) (surface_penalty.hpp), the node pushed back to the wall's surface
            const auto pen = wall_penalty(law, d, s.vol[i]);
            const double fn = pen.force;
            double f[3] = {fn * n[0], fn * n[1], fn * n[2]};
            if (normal && (law.restitution < 1 || law.friction > 0))
                mine.push_back({s.body[i],
                                static_cast<std::int32_t>(w),
                                static_cast<index_t>(i),
                                {f[0] * s.vol[i], f[1] * s.vol[i], f[2] * s.vol[i]},
                                law.friction,
                                law.restitution < 1});
            for (int q = 0; q < 3; ++q)
                s.f[3 * i + q] += f[q];
            const double F[3] = {-f[0] * s.vol[i], -f[1] * s.vol[i], -f[2] * s.vol[i]};
            const auto& c = pose[w].centre;
            const double r[3] = {x[0] - c[0], x[1] - c[1], x[2] - c[2]};
            add_reaction(fmp + 6 * w, F, r);
            energy += pen.energy;
            ++touching;
        }
    }
    if (normal) {
#pragma omp critical(pd_wall_records)
        st.records.insert(st.records.end(), mine.begin(), mine.end());
    }
    if (first >= 0) {
#pragma omp critical(pd_wall_beyond)
        if (load.beyond_node < 0 || first < load.beyond_node) {
            load.beyond_node = first;
            load.beyond_wall = first_wall;
        }
    }
}

} // namespace pd::solver
