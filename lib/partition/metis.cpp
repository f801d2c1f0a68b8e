// SPDX-License-Identifier: MIT
// The only file that includes metis.h (PIMPL rule, STYLE 2.1).
#include "core/errors.hpp"
#include "partition/graph.hpp"

#include <metis.h>

namespace pd::partition {

static_assert(sizeof(idx_t) == sizeof(std::int32_t), "Debian's METIS uses 32-bit idx_t");

std::vector<std::int32_t> metis_partition(const Graph& g, int num_parts) {
    const auto n = static_cast<idx_t>(g.num_vertices());
    if (num_parts < 1)
        throw InputError(fmt::format("number of parts must be at least 1, got {}", num_parts));
    if (num_parts > n)
        throw InputError(fmt::format("cannot split {} vertices into {} parts", n, num_parts));
    std::vector<std::int32_t> part(static_cast<std::size_t>(n), 0);
    if (num_parts == 1)
        return part;
    idx_t nvtxs = n, ncon = 1, nparts = num_parts, objval = 0;
    std::vector<idx_t> xadj(g.xadj.begin(), g.xadj.end()), adjncy(g.adjncy.begin(), g.adjncy.end()),
        vwgt(g.vwgt.begin(), g.vwgt.end()), adjwgt(g.adjwgt.begin(), g.adjwgt.end());
    std::vector<idx_t> out(static_cast<std::size_t>(n));
    idx_t options[METIS_NOPTIONS];
    METIS_SetDefaultOptions(options);
    options[METIS_OPTION_SEED] = 1; // reproducible
    options[METIS_OPTION_NUMBERING] = 0;
    idx_t* adj = adjncy.empty() ? nullptr : adjncy.data();
    idx_t* aw = adjwgt.empty() ? nullptr : adjwgt.data();
    const int rc = METIS_PartGraphKway(&nvtxs, &ncon, xadj.data(), adj, vwgt.data(), nullptr, aw,
                                       &nparts, nullptr, nullptr, options, &objval, out.data());
    if (rc != METIS_OK)
        throw InternalError(fmt::format("METIS failed with status {}", rc));
    for (std::size_t i = 0; i < part.size(); ++i)
        part[i] = static_cast<std::int32_t>(out[i]);
    return part;
}

} // namespace pd::partition
