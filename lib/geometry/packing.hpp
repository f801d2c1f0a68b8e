// SPDX-License-Identifier: MIT
// Grain placement: random non-overlapping packing of bounding circles/spheres inside a container
// shape (random sequential addition on a uniform grid, then overlap relaxation for what did not
// fit), regular lattices with jitter, and particle CSV files (x, y, z, r, orientation, shape).
#pragma once

#include "geometry/shapes.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace pd::geometry {

/// One grain instance. The grain with reference shape S (bounding radius R_S) is S rotated by
/// `orientation` about z, scaled by s = radius / R_S and moved to `center` (spec 2.5).
struct Grain {
    Vec3 center{0, 0, 0};   ///< m (z = 0 in 2D)
    double radius = 0;      ///< bounding radius of the instance, m
    double orientation = 0; ///< rad about z, in [0, 2 pi)
    std::int32_t shape = 0; ///< index into the caller's list of reference shapes
    bool operator==(const Grain&) const = default;
};

struct PackOptions {
    std::size_t count = 0; ///< number of grains (unless `radii` is given)
    double rmin = 0;       ///< bounding radii are drawn uniformly in [rmin, rmax], m
    double rmax = 0;
    std::vector<double> radii;          ///< if not empty: one grain per entry, radius in m
    std::vector<double> fractions{1.0}; ///< share of each shape index (normalised); counts are
                                        ///< rounded by largest remainder, then shuffled
    std::vector<std::int32_t> shapes;   ///< if not empty (size = number of grains): the shape of
                                        ///< each grain, overriding `fractions`
    double gap = 0;                 ///< minimum distance between bounding circles/spheres, and from
                                    ///< them to the container boundary, m
    std::uint64_t seed = 1;         ///< std::mt19937_64 seed; same seed -> identical output
    bool random_orientation = true; ///< uniform in [0, 2 pi); false: 0
    std::size_t attempts_per_grain = 2000; ///< random sequential addition tries per grain
    bool relax = true;                     ///< place the rest by overlap relaxation
    std::size_t max_relax_sweeps = 100000; ///< give up (InputError) after this many sweeps
    /// Give up (InputError) after this many grain steps (a placement try, a least-overlap try,
    /// a grain in a relaxation sweep); 0: no limit. pd-pack: 50 per node of its node limit.
    double max_work = 0;
};

/// What random_pack did (for logs and benchmarks).
struct PackStats {
    std::size_t placed_by_rsa = 0; ///< grains placed by random sequential addition
    std::size_t relaxed = 0;       ///< grains inserted with overlap and relaxed into place
    std::size_t sweeps = 0;        ///< relaxation sweeps
    double packing_fraction = 0;   ///< sum of bounding circle areas (spheres' volumes) / container
};

/// Random non-overlapping grains inside `container` (2D or 3D; its dimension decides).
/// Guarantees, checked before returning: |c_i - c_j| >= r_i + r_j + gap for every pair, and
/// container.clearance(c_i) >= r_i + gap for every grain (so the grain, in any orientation, lies
/// inside the container). Algorithm: radii, shapes and orientations are drawn first (in grain
/// order); grains are then placed largest first by random sequential addition with a uniform
/// cell grid (O(1) per try, O(N) overall); grains that find no room after attempts_per_grain
/// tries are inserted at the least-overlapping of 16 random spots and a Gauss-Seidel relaxation
/// pushes overlapping pairs apart and grains back inside until no constraint is violated.
/// Deterministic: same seed, same output (bit for bit). The random stream is std::mt19937_64(seed)
/// mapped to doubles by hand, not through std:: distributions, so it does not depend on the
/// standard library either. Throws InputError on bad options or if the grains do not fit (the
/// message gives the requested packing fraction).
std::vector<Grain> random_pack(const Shape& container, const PackOptions& opt,
                               PackStats* stats = nullptr);

struct LatticeOptions {
    Vec3 origin{0, 0, 0};                       ///< centre of grain (0, 0, 0), m
    std::array<std::size_t, 3> counts{1, 1, 1}; ///< grains along x, y, z (z: 1 in 2D)
    Vec3 spacing{0, 0, 0};                      ///< centre spacing along x, y, z, m
    bool stagger = false; ///< shift odd rows by spacing_x / 2 (hexagonal-like rows)
    int dimension = 2;    ///< 2: z = origin z for all grains
    double rmin = 0;      ///< radii uniform in [rmin, rmax], m (rmin = rmax: all equal)
    double rmax = 0;
    double jitter = 0; ///< each centre coordinate moves by U(-jitter, jitter) * spacing
    double gap = 0;    ///< required distance between bounding circles, m
    std::vector<double> fractions{1.0}; ///< shape shares, as in PackOptions
    std::uint64_t seed = 1;
    bool random_orientation = true;
};

/// Grains on a lattice (row-major: x fastest). Throws InputError if two grains come closer than
/// r_i + r_j + gap (spacing too small for rmax and jitter), naming the pair.
std::vector<Grain> lattice(const LatticeOptions& opt);

/// lattice(opt) keeping only grains with container.clearance(c) >= r + gap.
std::vector<Grain> lattice(const Shape& container, const LatticeOptions& opt);

/// Reads rows "x, y, z, r, orientation, shape" (m, m, m, m, rad, index >= 0). A first line that
/// is not numeric is a header; blank lines and lines starting with '#' are skipped. Throws
/// InputError naming the file and line on anything else.
std::vector<Grain> read_particle_csv(const std::string& path);

/// Writes grains with the header "x,y,z,r,orientation,shape" (17 significant digits).
void write_particle_csv(const std::string& path, const std::vector<Grain>& grains);

/// Sum of the grains' bounding circle areas (2D) or sphere volumes (3D) / container measure.
double packing_fraction(const Shape& container, const std::vector<Grain>& grains);

} // namespace pd::geometry
