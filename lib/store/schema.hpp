// SPDX-License-Identifier: MIT
// pd-file schema v1: every dataset path pdgrain reads or writes, and the version rules.
// Normative description: data-schema/pd-file.md; machine-readable: data-schema/pd-file.schema.json
// (a test keeps the three in step). store/ is the only code that knows these paths.
#pragma once

#include <string>

namespace pd::h5 {
class File;
}

namespace pd::store {

inline constexpr const char* schema_name = "pd-file";
inline constexpr int schema_major = 1;
inline constexpr int schema_minor = 9; // kept equal to schema_version (raise_version compares them)
inline constexpr int schema_patch = 1;
inline constexpr const char* schema_version = "1.9.1";

namespace path {
// root attributes: schema, schema_version, units, dimension, planar, thickness, title
inline constexpr const char* h5md = "/h5md";
inline constexpr const char* parameters_scene = "/parameters/scene";
inline constexpr const char* parameters_overrides = "/parameters/overrides"; // pd-pack --set
inline constexpr const char* materials = "/materials";
inline constexpr const char* reference_meshes = "/reference_meshes";
inline constexpr const char* bodies = "/bodies";
inline constexpr const char* nodes = "/nodes";
inline constexpr const char* bonds = "/bonds";
inline constexpr const char* contact = "/contact";
inline constexpr const char* walls = "/walls";
inline constexpr const char* wall_meshes = "/walls/mesh"; // /walls/mesh/<k>/{points,cells}
inline constexpr const char* loading = "/loading";
inline constexpr const char* cracks = "/cracks";
inline constexpr const char* solver = "/solver";
inline constexpr const char* partition = "/partition";
inline constexpr const char* particles = "/particles/nodes";
inline constexpr const char* observables = "/observables";
inline constexpr const char* provenance = "/provenance";
inline constexpr const char* checkpoints = "/checkpoints";
} // namespace path

/// Throws SchemaError unless `f` is a pd-file whose major version this build reads
/// (a newer major version is refused with a message naming both versions).
void check_version(const h5::File& f);
/// Raises /@schema_version to this build's when the file's is older (a tool that adds objects of
/// a newer MINOR version to an existing file); never lowers it.
void raise_version(h5::File& f);

} // namespace pd::store
