// SPDX-License-Identifier: MIT
// pd-file validator driven by data-schema/pd-file.schema.json, embedded at build time. The same
// rules as data-schema/check_pd_file.py (presence, kind, dtype, shape, unit, values, ranges, CSR,
// finiteness, z = 0 in 2D), except two the h5 layer cannot see yet: hard links (H5MD step/time)
// and extendible first axes. Used by `pd-post --check`.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace pd::h5 {
class File;
}

namespace pd::post {

/// The schema JSON this build embeds (a copy of data-schema/pd-file.schema.json).
std::string_view schema_json();

/// Violations of `f` against the embedded schema, each "<object path>: <problem>" (attributes as
/// "<object>@<name>"). Empty means valid. A newer MAJOR schema_version yields one violation and
/// stops. Reads every numeric dataset once, a block of rows at a time. Any rank may call.
std::vector<std::string> check(const h5::File& f);

} // namespace pd::post
