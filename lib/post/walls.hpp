// SPDX-License-Identifier: MIT
// walls.csv: the reactions of the rigid walls over time, against their displacement. Per wall k:
// displacement wall_<k>_disp_{x,y,z} = /walls/velocity * time (rigid translation since t = 0),
// force wall_<k>_force_{x,y,z} and moment wall_<k>_moment_{x,y,z} (the observables wall_force
// and wall_moment, copied exactly), wall_<k>_normal_force = force . normal for planes (empty for
// circles), and with a length or area L, wall_<k>_stress_{x,y,z} = force / L. Then per meshed
// wall (a fixed or driven body b, the observables body_force and body_moment):
// body_<b>_disp_{x,y,z} (mean displacement its conditions prescribe; 0 for a fixed body),
// body_<b>_force_{x,y,z}, body_<b>_moment_{x,y,z} (about its centroid), body_<b>_stress_{x,y,z}.
#pragma once

#include "model/model.hpp"

#include <cstddef>
#include <string>

namespace pd::h5 {
class File;
}

namespace pd::post {

/// Writes the wall table of `f` (walls from `m`) to `csv_path`; returns the number of data rows.
/// `stress_length` <= 0 writes no stress columns (in 2D a length, m: the force is per unit
/// thickness; in 3D an area, m2). Throws SchemaError if wall_force/wall_moment disagree with the
/// number of walls (or body_force/body_moment with body_force/body), or if the file has no
/// reaction at all, InputError if the CSV cannot be written.
std::size_t write_walls_csv(const h5::File& f, const model::Model& m, const std::string& csv_path,
                            double stress_length = 0);

} // namespace pd::post
