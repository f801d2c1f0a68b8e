// SPDX-License-Identifier: MIT
// observables.csv: every observable series of a pd-file as one table, one row per observation.
// Columns: step,time, then the series of store::observable_list() in its order, then any other
// series under /observables (the wall reactions wall_force, wall_moment) in name order. A scalar
// series is one column <name>; a standard 3-vector <name>_x,_y,_z; any other series, (rows,
// items, 3), <name>_<k>_x,_y,_z per item k.
// Numbers are printed with 17 significant digits (exact round trip).
#pragma once

#include <cstddef>
#include <string>

namespace pd::h5 {
class File;
}

namespace pd::post {

/// Writes the observables of `f` to `csv_path`; returns the number of data rows. Throws
/// SchemaError if a standard series is missing or the series disagree in length, InputError if
/// the CSV cannot be written.
std::size_t write_observables_csv(const h5::File& f, const std::string& csv_path);

} // namespace pd::post
