// SPDX-License-Identifier: MIT
#include "store/schema.hpp"

#include "core/errors.hpp"
#include "h5/file.hpp"

#include <cstdio>
#include <tuple>

namespace pd::store {

void check_version(const h5::File& f) {
    if (!f.has_attr("/", "schema") || f.attr_string("/", "schema") != schema_name)
        throw SchemaError(f.name(), "/",
                          "not a pd-file (root attribute 'schema' is not 'pd-file')");
    if (!f.has_attr("/", "schema_version"))
        throw SchemaError(f.name(), "/", "missing root attribute 'schema_version'");
    std::string v = f.attr_string("/", "schema_version");
    int major = 0, minor = 0, patch = 0;
    if (std::sscanf(v.c_str(), "%d.%d.%d", &major, &minor, &patch) != 3)
        throw SchemaError(f.name(), "/", "schema_version '" + v + "' is not MAJOR.MINOR.PATCH");
    if (major > schema_major)
        throw SchemaError(f.name(), "/",
                          fmt::format("written with pd-file {}, this pdgrain reads pd-file {}.x "
                                      "(upgrade pdgrain)",
                                      v, schema_major));
    if (major < schema_major)
        throw SchemaError(
            f.name(), "/",
            fmt::format("pd-file {} is older than {}.x and not readable", v, schema_major));
}

void raise_version(h5::File& f) {
    int v[3] = {0, 0, 0};
    const std::string s =
        f.has_attr("/", "schema_version") ? f.attr_string("/", "schema_version") : std::string();
    if (std::sscanf(s.c_str(), "%d.%d.%d", &v[0], &v[1], &v[2]) == 3 &&
        std::make_tuple(v[0], v[1], v[2]) >=
            std::make_tuple(schema_major, schema_minor, schema_patch))
        return;
    f.set_attr("/", "schema_version", std::string(schema_version));
}

} // namespace pd::store
