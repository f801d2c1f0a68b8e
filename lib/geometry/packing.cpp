// SPDX-License-Identifier: MIT
// Random packing (random sequential addition + Gauss-Seidel overlap relaxation) on a uniform
// cell grid, and lattices (the particle CSV format: particle_csv.cpp). All randomness comes from
// one std::mt19937_64 mapped to doubles by hand (std distributions differ between libraries).
#include "geometry/packing.hpp"

#include "core/errors.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <random>

namespace pd::geometry {

namespace {

constexpr double two_pi = 2 * std::numbers::pi;

/// Portable uniform draws from mt19937_64.
class Rng {
  public:
    explicit Rng(std::uint64_t seed)
        : g_(seed) {}
    double uniform() { return static_cast<double>(g_() >> 11) * 0x1.0p-53; } ///< [0, 1)
    double uniform(double a, double b) { return a + (b - a) * uniform(); }
    std::size_t index(std::size_t n) { ///< [0, n)
        return std::min(n - 1, static_cast<std::size_t>(uniform() * static_cast<double>(n)));
    }

  private:
    std::mt19937_64 g_;
};

/// Uniform cell grid with linked lists (head per cell, next per grain).
class Grid {
  public:
    Grid(const std::array<double, 6>& box, double cell, int dim, std::size_t n)
        : dim_(dim) {
        // Keep the number of cells O(n + 1e6): very small grains in a huge container get
        // coarser cells, which costs time but never correctness.
        const double max_cells = std::max(1e6, 8.0 * static_cast<double>(n));
        for (;;) {
            double total = 1;
            for (int i = 0; i < 3; ++i) {
                lo_[i] = box[i];
                n_[i] = i < dim ? std::max<long>(
                                      1, static_cast<long>(std::ceil((box[i + 3] - box[i]) / cell)))
                                : 1;
                total *= static_cast<double>(n_[i]);
            }
            if (total <= max_cells)
                break;
            cell *= 1.5;
        }
        inv_ = 1 / cell;
        head_.assign(static_cast<std::size_t>(n_[0] * n_[1] * n_[2]), -1);
        next_.assign(n, -1);
    }
    void clear() { std::fill(head_.begin(), head_.end(), -1); }
    void insert(std::int32_t i, const Vec3& p) {
        const auto c = cell_of(p);
        const std::size_t k = index(c[0], c[1], c[2]);
        next_[static_cast<std::size_t>(i)] = head_[k];
        head_[k] = i;
    }
    /// Calls f(j) for every grain in the 3^dim cells around p (all j with |c_j - p| < cell).
    /// The grid's sizes and lists are read into locals first: f may write through references
    /// the compiler cannot tell apart from them, which would reload them on every iteration.
    template <class F>
    void for_near(const Vec3& p, F&& f) const {
        const auto c = cell_of(p);
        const long dz = dim_ == 3 ? 1 : 0;
        const long nx = n_[0], ny = n_[1], nz = n_[2];
        const std::int32_t* head = head_.data();
        const std::int32_t* next = next_.data();
        for (long z = std::max(0L, c[2] - dz); z <= std::min(nz - 1, c[2] + dz); ++z)
            for (long y = std::max(0L, c[1] - 1); y <= std::min(ny - 1, c[1] + 1); ++y)
                for (long x = std::max(0L, c[0] - 1); x <= std::min(nx - 1, c[0] + 1); ++x)
                    for (std::int32_t j = head[static_cast<std::size_t>((z * ny + y) * nx + x)];
                         j >= 0; j = next[static_cast<std::size_t>(j)])
                        f(j);
    }

  private:
    std::array<long, 3> cell_of(const Vec3& p) const {
        std::array<long, 3> c{};
        for (int i = 0; i < 3; ++i) {
            const double v = std::floor((p[i] - lo_[i]) * inv_);
            c[i] = std::clamp(static_cast<long>(std::clamp(v, -1.0, 1e18)), 0L, n_[i] - 1);
        }
        return c;
    }
    std::size_t index(long x, long y, long z) const {
        return static_cast<std::size_t>((z * n_[1] + y) * n_[0] + x);
    }
    int dim_;
    std::array<double, 3> lo_{};
    std::array<long, 3> n_{};
    double inv_ = 1;
    std::vector<std::int32_t> head_, next_;
};

double dist2(const Vec3& a, const Vec3& b) {
    return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
           (a[2] - b[2]) * (a[2] - b[2]);
}

/// Shape index of each of n grains: counts by largest remainder, then a Fisher-Yates shuffle.
std::vector<std::int32_t> draw_shapes(std::size_t n, const std::vector<double>& fractions,
                                      Rng& rng) {
    if (fractions.empty())
        throw InputError("packing: 'fractions' needs at least one entry");
    double total = 0;
    for (std::size_t k = 0; k < fractions.size(); ++k) {
        if (!(fractions[k] >= 0) || !std::isfinite(fractions[k]))
            throw InputError(
                fmt::format("packing: fractions[{}] = {} must be >= 0", k, fractions[k]));
        total += fractions[k];
    }
    if (!(total > 0))
        throw InputError("packing: the shape fractions sum to 0");
    std::vector<std::size_t> count(fractions.size());
    std::vector<std::pair<double, std::size_t>> rest;
    std::size_t assigned = 0;
    for (std::size_t k = 0; k < fractions.size(); ++k) {
        const double want = static_cast<double>(n) * fractions[k] / total;
        count[k] = static_cast<std::size_t>(std::floor(want));
        assigned += count[k];
        rest.push_back({-(want - std::floor(want)), k}); // largest remainder first, then by k
    }
    std::sort(rest.begin(), rest.end());
    for (std::size_t i = 0; assigned < n; ++i, ++assigned)
        ++count[rest[i % rest.size()].second];
    std::vector<std::int32_t> s;
    s.reserve(n);
    for (std::size_t k = 0; k < count.size(); ++k)
        s.insert(s.end(), count[k], static_cast<std::int32_t>(k));
    for (std::size_t i = n; i > 1; --i)
        std::swap(s[i - 1], s[rng.index(i)]);
    return s;
}

/// Index of the first pair closer than r_i + r_j + gap, or {-1, -1}.
std::pair<std::int32_t, std::int32_t> first_overlap(const std::vector<Grain>& g, double gap,
                                                    int dim) {
    if (g.empty())
        return {-1, -1};
    const double inf = std::numeric_limits<double>::infinity();
    std::array<double, 6> box{inf, inf, inf, -inf, -inf, -inf};
    double rmax = 0;
    for (const auto& x : g) {
        for (int i = 0; i < 3; ++i) {
            box[i] = std::min(box[i], x.center[i]);
            box[i + 3] = std::max(box[i + 3], x.center[i]);
        }
        rmax = std::max(rmax, x.radius);
    }
    Grid grid(box, 2 * rmax + gap, dim, g.size());
    for (std::size_t i = 0; i < g.size(); ++i)
        grid.insert(static_cast<std::int32_t>(i), g[i].center);
    std::pair<std::int32_t, std::int32_t> bad{-1, -1};
    for (std::size_t i = 0; i < g.size() && bad.first < 0; ++i)
        grid.for_near(g[i].center, [&](std::int32_t j) {
            if (static_cast<std::size_t>(j) <= i || bad.first >= 0)
                return;
            const double d = g[i].radius + g[static_cast<std::size_t>(j)].radius + gap;
            if (dist2(g[i].center, g[static_cast<std::size_t>(j)].center) < d * d)
                bad = {static_cast<std::int32_t>(i), j};
        });
    return bad;
}

double ball_measure(double r, int dim) {
    return dim == 2 ? std::numbers::pi * r * r : 4.0 / 3.0 * std::numbers::pi * r * r * r;
}

} // namespace

double packing_fraction(const Shape& container, const std::vector<Grain>& grains) {
    double sum = 0;
    for (const auto& g : grains)
        sum += ball_measure(g.radius, container.dimension());
    return sum / container.area_or_volume();
}

// ------------------------------------------------------------------------------------------------
namespace {

/// Step 1 of random_pack: radii, shapes and orientations, in grain order.
std::vector<Grain> draw_grains(const PackOptions& opt, Rng& rng) {
    std::vector<Grain> g;
    if (!opt.radii.empty()) {
        g.resize(opt.radii.size());
        for (std::size_t i = 0; i < g.size(); ++i) {
            if (!(opt.radii[i] > 0) || !std::isfinite(opt.radii[i]))
                throw InputError(fmt::format("random_pack: radii[{}] = {} must be a positive "
                                             "length in m",
                                             i, opt.radii[i]));
            g[i].radius = opt.radii[i];
        }
    } else {
        if (!(opt.rmin > 0) || !(opt.rmax >= opt.rmin) || !std::isfinite(opt.rmax))
            throw InputError(fmt::format("random_pack: need 0 < rmin <= rmax, got rmin = {}, "
                                         "rmax = {} m",
                                         opt.rmin, opt.rmax));
        g.resize(opt.count);
        for (auto& x : g)
            x.radius = rng.uniform(opt.rmin, opt.rmax);
    }
    if (!(opt.gap >= 0) || !std::isfinite(opt.gap))
        throw InputError(fmt::format("random_pack: gap = {} m must be >= 0", opt.gap));
    const std::size_t n = g.size();
    if (!opt.shapes.empty()) {
        if (opt.shapes.size() != n)
            throw InputError(fmt::format("random_pack: 'shapes' has {} entries for {} grains",
                                         opt.shapes.size(), n));
        for (std::size_t i = 0; i < n; ++i) {
            if (opt.shapes[i] < 0)
                throw InputError(
                    fmt::format("random_pack: shapes[{}] = {} must be >= 0", i, opt.shapes[i]));
            g[i].shape = opt.shapes[i];
        }
    } else {
        const auto s = draw_shapes(n, opt.fractions, rng);
        for (std::size_t i = 0; i < n; ++i)
            g[i].shape = s[i];
    }
    for (auto& x : g)
        x.orientation = opt.random_orientation ? two_pi * rng.uniform() : 0.0;
    return g;
}

double min_radius(const std::vector<Grain>& g, double rmax) {
    double rmin = rmax;
    for (const auto& x : g)
        rmin = std::min(rmin, x.radius);
    return rmin;
}

/// Fails fast (issue 13) when the grains cannot fit: no arrangement of equal discs (spheres) is
/// denser than the hexagonal (fcc) one, 0.9069 (0.7405); unequal radii can fill part of the gaps
/// left, in proportion to their spread (above that bound the relaxation ran for minutes before
/// giving up); and the largest grain must fit the container's bounding box.
void check_room(const Shape& container, const PackOptions& opt, const std::vector<Grain>& g,
                double rmax, double requested) {
    const int dim = container.dimension();
    const double rmin = min_radius(g, rmax);
    const double densest = dim == 3 ? 0.7405 : 0.9069;
    const double bound = densest + (1 - densest) * (1 - rmin / rmax);
    if (!(requested <= bound))
        throw InputError(fmt::format(
            "random_pack: {} grains (radius {:g}..{:g} m) need a packing fraction of {:.3f} "
            "in {} (area or volume {:.4g}), above the {:.3f} that grains of these radii can "
            "reach: fewer or smaller grains, or a larger container",
            g.size(), rmin, rmax, requested, container.name(), container.area_or_volume(), bound));
    const auto box = container.bounding_box();
    for (int i = 0; i < dim; ++i)
        if (box[i + 3] - box[i] < 2 * (rmax + opt.gap))
            throw InputError(fmt::format("random_pack: a grain of radius {} m (+ gap {} m) does "
                                         "not fit in container {}",
                                         rmax, opt.gap, container.name()));
}

/// Steps 2-4 of random_pack on drawn grains: placement, relaxation, verification. Every random
/// draw comes from one Rng, in a fixed order, so a seed gives one result.
class Packer {
  public:
    Packer(const Shape& container, const PackOptions& opt, std::vector<Grain>& g, Rng& rng,
           double rmax, double requested)
        : container_(container)
        , opt_(opt)
        , g_(g)
        , rng_(rng)
        , dim_(container.dimension())
        , box_(container.bounding_box())
        , rmax_(rmax)
        , requested_(requested)
        , grid_(box_, 2 * rmax + opt.gap, dim_, g.size()) {}

    /// Random sequential addition, largest grains first; returns the grains that found no room.
    std::vector<std::size_t> place_by_rsa() {
        const std::size_t n = g_.size();
        std::vector<std::size_t> order(n);
        std::iota(order.begin(), order.end(), std::size_t{0});
        std::stable_sort(order.begin(), order.end(),
                         [&](std::size_t a, std::size_t b) { return g_[a].radius > g_[b].radius; });
        std::vector<std::size_t> deferred;
        std::size_t failures_in_a_row = 0;
        for (std::size_t i : order) {
            bool placed = false;
            // Once many grains in a row found no room the pack is jammed: stop trying.
            const std::size_t tries = failures_in_a_row >= 20 ? 0 : opt_.attempts_per_grain;
            for (std::size_t t = 0; t < tries && !placed; ++t) {
                spend(1);
                const Vec3 p = sample(g_[i].radius);
                if (free_of_overlap(p, g_[i].radius, n) && fits_container(p, g_[i].radius)) {
                    g_[i].center = p;
                    grid_.insert(static_cast<std::int32_t>(i), p);
                    placed = true;
                }
            }
            if (placed) {
                failures_in_a_row = 0;
            } else {
                ++failures_in_a_row;
                deferred.push_back(i);
            }
        }
        return deferred;
    }

    /// Inserts each deferred grain where it overlaps least (of 16 positions with clearance).
    void insert_least_overlap(const std::vector<std::size_t>& deferred) {
        for (std::size_t i : deferred) {
            Vec3 best{0, 0, 0};
            double best_pen = std::numeric_limits<double>::infinity();
            for (int t = 0, found = 0; found < 16 && t < 100000; ++t) {
                spend(1);
                const Vec3 p = sample(g_[i].radius);
                if (!fits_container(p, g_[i].radius))
                    continue;
                ++found;
                double pen = 0;
                grid_.for_near(p, [&](std::int32_t j) {
                    const auto& o = g_[static_cast<std::size_t>(j)];
                    pen = std::max(pen, g_[i].radius + o.radius + opt_.gap -
                                            std::sqrt(dist2(p, o.center)));
                });
                if (pen < best_pen) {
                    best_pen = pen;
                    best = p;
                }
            }
            if (!std::isfinite(best_pen))
                throw fail("no position inside the container has enough clearance");
            g_[i].center = best;
            grid_.insert(static_cast<std::int32_t>(i), best);
        }
    }

    /// Gauss-Seidel sweeps pushing overlapping pairs apart and grains back into the container,
    /// until a sweep moves nothing; returns the number of sweeps (throws after the maximum).
    std::size_t relax(std::size_t relaxed) {
        std::size_t sweeps = 1;
        for (; sweeps <= opt_.max_relax_sweeps; ++sweeps) {
            spend(static_cast<double>(g_.size()));
            grid_.clear();
            for (std::size_t i = 0; i < g_.size(); ++i)
                grid_.insert(static_cast<std::int32_t>(i), g_[i].center);
            const bool pairs_moved = push_pairs_apart();
            if (!push_into_container() && !pairs_moved)
                return sweeps;
        }
        throw fail(fmt::format("{} grains were relaxed for {} sweeps without removing every "
                               "overlap",
                               relaxed, opt_.max_relax_sweeps));
    }

    /// Checks the guarantees independently of how the grains were placed.
    void verify() const {
        for (std::size_t i = 0; i < g_.size(); ++i)
            if (!fits_container(g_[i].center, g_[i].radius))
                throw InternalError(fmt::format("random_pack: grain {} ends outside the "
                                                "container (please report)",
                                                i));
        if (const auto bad = first_overlap(g_, opt_.gap, dim_); bad.first >= 0)
            throw InternalError(fmt::format("random_pack: grains {} and {} overlap (please "
                                            "report)",
                                            bad.first, bad.second));
    }

    InputError fail(const std::string& why) const {
        return InputError(fmt::format("random_pack: cannot place {} grains (radius {:g}..{:g} m, "
                                      "gap {:g} m) in {}: requested packing fraction {:.3f}; {}",
                                      g_.size(), min_radius(g_, rmax_), rmax_, opt_.gap,
                                      container_.name(), requested_, why));
    }

  private:
    /// Counts grain steps against opt.max_work.
    void spend(double steps) {
        work_ += steps;
        if (opt_.max_work > 0 && work_ > opt_.max_work)
            throw fail(fmt::format("gave up after {:.3g} placement tries and relaxation steps "
                                   "(the limit grows with the node limit, pd-pack --max-nodes)",
                                   work_));
    }

    /// Push targets carry a relative margin so that rounding cannot leave a pair a hair short.
    static constexpr double margin = 1e-9;

    bool free_of_overlap(const Vec3& p, double r, std::size_t self) const {
        bool ok = true;
        grid_.for_near(p, [&](std::int32_t j) {
            const auto& o = g_[static_cast<std::size_t>(j)];
            const double d = r + o.radius + opt_.gap;
            if (ok && static_cast<std::size_t>(j) != self && dist2(p, o.center) < d * d)
                ok = false;
        });
        return ok;
    }
    bool fits_container(const Vec3& p, double r) const {
        return container_.clearance(p[0], p[1], p[2]) >= r + opt_.gap;
    }
    Vec3 sample(double r) {
        Vec3 p{0, 0, 0};
        for (int i = 0; i < dim_; ++i)
            p[i] = rng_.uniform(box_[i] + r + opt_.gap, box_[i + 3] - r - opt_.gap);
        return p;
    }

    /// Moves each overlapping pair apart symmetrically along the line of centres (a random
    /// direction for coincident centres); true if any moved.
    bool push_pairs_apart() {
        bool moved = false;
        for (std::size_t i = 0; i < g_.size(); ++i) {
            grid_.for_near(g_[i].center, [&](std::int32_t jj) {
                const auto j = static_cast<std::size_t>(jj);
                if (j <= i)
                    return;
                const double target = g_[i].radius + g_[j].radius + opt_.gap;
                const double d2 = dist2(g_[i].center, g_[j].center);
                if (d2 >= target * target)
                    return;
                double d = std::sqrt(d2);
                Vec3 u{0, 0, 0};
                if (d > 0) {
                    for (int k = 0; k < dim_; ++k)
                        u[k] = (g_[j].center[k] - g_[i].center[k]) / d;
                } else { // coincident centres: a random direction
                    const double a = two_pi * rng_.uniform();
                    u = {std::cos(a), std::sin(a), 0};
                }
                const double push = 0.5 * (target * (1 + margin) - d);
                for (int k = 0; k < dim_; ++k) {
                    g_[i].center[k] -= push * u[k];
                    g_[j].center[k] += push * u[k];
                }
                moved = true;
            });
        }
        return moved;
    }

    /// Moves each grain short of clearance along the clearance gradient (the inward normal, by
    /// finite differences), up to 4 steps; true if any moved or is still short.
    bool push_into_container() {
        const double fd_step = 1e-7 * rmax_;
        bool moved = false;
        for (auto& x : g_) {
            const double need = x.radius + opt_.gap;
            auto& c = x.center;
            double cl = container_.clearance(c[0], c[1], c[2]);
            for (int it = 0; it < 4 && cl < need; ++it) {
                Vec3 grad{0, 0, 0};
                double norm = 0;
                for (int k = 0; k < dim_; ++k) {
                    Vec3 a = c, b = c;
                    a[k] += fd_step;
                    b[k] -= fd_step;
                    grad[k] = (container_.clearance(a[0], a[1], a[2]) -
                               container_.clearance(b[0], b[1], b[2])) /
                              (2 * fd_step);
                    norm += grad[k] * grad[k];
                }
                norm = std::sqrt(norm);
                if (!(norm > 1e-6)) { // on a ridge of the distance: step to a random side
                    const double a = two_pi * rng_.uniform();
                    grad = {std::cos(a), std::sin(a), 0};
                    norm = 1;
                }
                const double step = need * (1 + margin) - cl + margin * rmax_;
                for (int k = 0; k < dim_; ++k)
                    c[k] += step * grad[k] / norm;
                cl = container_.clearance(c[0], c[1], c[2]);
                moved = true;
            }
            if (cl < need)
                moved = true;
        }
        return moved;
    }

    const Shape& container_;
    const PackOptions& opt_;
    std::vector<Grain>& g_;
    Rng& rng_;
    int dim_;
    std::array<double, 6> box_;
    double rmax_, requested_;
    Grid grid_;
    double work_ = 0;
};

} // namespace

std::vector<Grain> random_pack(const Shape& container, const PackOptions& opt, PackStats* stats) {
    Rng rng(opt.seed);
    std::vector<Grain> g = draw_grains(opt, rng);
    const std::size_t n = g.size();
    if (n == 0)
        return g;
    double rmax = 0, total = 0;
    for (const auto& x : g) {
        rmax = std::max(rmax, x.radius);
        total += ball_measure(x.radius, container.dimension());
    }
    const double requested = total / container.area_or_volume();
    check_room(container, opt, g, rmax, requested);

    Packer packer(container, opt, g, rng, rmax, requested);
    const auto deferred = packer.place_by_rsa();
    PackStats st;
    st.placed_by_rsa = n - deferred.size();
    st.relaxed = deferred.size();
    if (!deferred.empty() && !opt.relax)
        throw packer.fail(fmt::format(
            "{} did not fit by random sequential addition and relax = false", deferred.size()));
    // Relaxation: insert the rest where they overlap least, then push apart until valid.
    if (!deferred.empty()) {
        packer.insert_least_overlap(deferred);
        st.sweeps = packer.relax(deferred.size());
    }
    packer.verify();
    st.packing_fraction = requested;
    if (stats)
        *stats = st;
    return g;
}

// ------------------------------------------------------------------------------------------------
std::vector<Grain> lattice(const LatticeOptions& opt) {
    if (opt.dimension != 2 && opt.dimension != 3)
        throw InputError(fmt::format("lattice: dimension must be 2 or 3, got {}", opt.dimension));
    if (opt.dimension == 2 && opt.counts[2] != 1)
        throw InputError(
            fmt::format("lattice: a 2D lattice has 1 layer along z, got {}", opt.counts[2]));
    if (!(opt.rmin > 0) || !(opt.rmax >= opt.rmin))
        throw InputError(fmt::format("lattice: need 0 < rmin <= rmax, got rmin = {}, rmax = {} m",
                                     opt.rmin, opt.rmax));
    if (!(opt.jitter >= 0) || !(opt.jitter < 0.5))
        throw InputError(fmt::format("lattice: jitter must be in [0, 0.5), got {}", opt.jitter));
    for (int k = 0; k < opt.dimension; ++k)
        if (opt.counts[static_cast<std::size_t>(k)] > 1 && !(opt.spacing[k] > 0))
            throw InputError(fmt::format("lattice: spacing along axis {} must be > 0, got {} m", k,
                                         opt.spacing[k]));
    Rng rng(opt.seed);
    const std::size_t n = opt.counts[0] * opt.counts[1] * opt.counts[2];
    std::vector<Grain> g(n);
    const std::size_t nx = opt.counts[0], ny = opt.counts[1];
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t ix = i % nx, iy = (i / nx) % ny, iz = i / (nx * ny);
        Vec3 c = opt.origin;
        c[0] += (static_cast<double>(ix) + (opt.stagger && iy % 2 ? 0.5 : 0.0)) * opt.spacing[0];
        c[1] += static_cast<double>(iy) * opt.spacing[1];
        if (opt.dimension == 3)
            c[2] += static_cast<double>(iz) * opt.spacing[2];
        for (int k = 0; k < opt.dimension; ++k)
            c[k] += opt.jitter * opt.spacing[k] * rng.uniform(-1, 1);
        g[i].center = c;
        g[i].radius = opt.rmin == opt.rmax ? opt.rmin : rng.uniform(opt.rmin, opt.rmax);
    }
    const auto s = draw_shapes(n, opt.fractions, rng);
    for (std::size_t i = 0; i < n; ++i) {
        g[i].shape = s[i];
        g[i].orientation = opt.random_orientation ? two_pi * rng.uniform() : 0.0;
    }
    if (const auto bad = first_overlap(g, opt.gap, opt.dimension); bad.first >= 0)
        throw InputError(fmt::format("lattice: grains {} and {} are closer than r_i + r_j + gap "
                                     "(spacing ({}, {}, {}) m too small for rmax = {} m, jitter "
                                     "= {}, gap = {} m)",
                                     bad.first, bad.second, opt.spacing[0], opt.spacing[1],
                                     opt.spacing[2], opt.rmax, opt.jitter, opt.gap));
    return g;
}

std::vector<Grain> lattice(const Shape& container, const LatticeOptions& opt) {
    if (container.dimension() != opt.dimension)
        throw InputError(fmt::format("lattice: {}D lattice in a {}D container", opt.dimension,
                                     container.dimension()));
    std::vector<Grain> all = lattice(opt), kept;
    for (const auto& x : all)
        if (container.clearance(x.center[0], x.center[1], x.center[2]) >= x.radius + opt.gap)
            kept.push_back(x);
    return kept;
}

} // namespace pd::geometry
