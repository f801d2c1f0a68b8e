// SPDX-License-Identifier: MIT
#include "store/provenance.hpp"

#include "h5/file.hpp"
#include "store/schema.hpp"

#include <algorithm>

namespace pd::store {

void append_provenance(h5::File& f, const RunInfo& run, int exit_status) {
    f.create_group(path::provenance);
    const auto existing = f.list(path::provenance);
    std::string tool = run.tool;
    std::replace(tool.begin(), tool.end(), '-', '_');
    const std::string g = fmt::format("{}/{:03d}_{}", path::provenance, existing.size(), tool);
    f.create_group(g);
    f.set_attr(g, "tool", run.tool);
    f.set_attr(g, "version", run.version);
    f.set_attr(g, "git_commit", run.git_commit);
    f.set_attr(g, "command_line", run.command_line);
    f.set_attr(g, "start_time", run.start_time);
    f.set_attr(g, "end_time", utc_now());
    f.set_attr(g, "mpi_ranks", static_cast<std::int32_t>(run.mpi_ranks));
    f.set_attr(g, "threads", static_cast<std::int32_t>(run.threads));
    f.set_attr(g, "exit_status", static_cast<std::int32_t>(exit_status));
    if (!run.overrides.empty())
        f.set_attr(g, "overrides", run.overrides);
    f.flush();
}

} // namespace pd::store
