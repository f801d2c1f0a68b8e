// SPDX-License-Identifier: MIT
#include "store/frames.hpp"

#include "core/errors.hpp"
#include "h5/file.hpp"
#include "store/schema.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pd::store {

namespace {

/// Rows per chunk of the frames' step and time, and of every observable series (early
/// allocation: a chunk takes its whole size in the file when the dataset grows into it).
constexpr std::uint64_t frame_step_chunk = 1024;
constexpr std::uint64_t observable_chunk = 4096;
const std::string P = path::particles;
const std::string O = path::observables;

std::string field_path(const std::string& field) {
    return P + "/" + field;
}
} // namespace

const std::vector<FieldInfo>& frame_fields() {
    static const std::vector<FieldInfo> f{{"position", 3, "m"},     {"velocity", 3, "m s-1"},
                                          {"displacement", 3, "m"}, {"force", 3, "N"},
                                          {"damage", 1, "1"},       {"damage_z", 1, "1"},
                                          {"fragment", 1, "1"},     {"broken_bonds", 1, "1"}};
    return f;
}

const std::vector<ObservableInfo>& observable_list() {
    static const std::vector<ObservableInfo> o{{"kinetic_energy", 1, "J"},
                                               {"elastic_energy", 1, "J"},
                                               {"contact_energy", 1, "J"},
                                               {"external_work", 1, "J"},
                                               {"momentum", 3, "kg m s-1"},
                                               {"contact_count", 1, "1"},
                                               {"broken_bonds", 1, "1"},
                                               // pd-file 1.2: the energy balance
                                               {"fracture_energy", 1, "J", false},
                                               {"damping_dissipation", 1, "J", false},
                                               {"friction_dissipation", 1, "J", false},
                                               {"viscous_dissipation", 1, "J", false},
                                               {"gravity_potential", 1, "J", false}};
    return o;
}

static const FieldInfo& field_info(const std::string& name) {
    for (const auto& fi : frame_fields())
        if (fi.name == name)
            return fi;
    throw InputError("unknown frame field '" + name +
                     "' (known: position, velocity, "
                     "displacement, force, damage, damage_z, fragment, broken_bonds)");
}

void write_particle_constants(h5::File& f, const std::vector<std::int32_t>& species,
                              const std::vector<double>& mass) {
    f.write(P + "/species", species);
    f.set_attr(P + "/species", "unit", "1");
    f.write(P + "/mass", mass);
    f.set_attr(P + "/mass", "unit", "kg");
}

FrameWriter::FrameWriter(h5::File& f, std::size_t num_nodes, std::vector<std::string> fields,
                         int deflate)
    : f_(f)
    , n_(num_nodes) {
    fields_.push_back("position");
    for (auto& name : fields)
        if (name != "position" &&
            std::find(fields_.begin(), fields_.end(), name) == fields_.end()) {
            field_info(name);
            fields_.push_back(name);
        }
    if (f_.exists(field_path("position") + "/value")) { // appending (restart)
        frames_ = f_.shape(field_path("position") + "/step")[0];
        for (auto& name : fields_)
            if (!f_.exists(field_path(name) + "/value"))
                throw SchemaError(f_.name(), field_path(name),
                                  "missing; cannot append frames with a different field set");
        return;
    }
    f_.create_group(P + "/box");
    f_.set_attr(P + "/box", "dimension", std::int32_t{3});
    f_.set_attr(P + "/box", "boundary", std::vector<std::string>{"none", "none", "none"});
    const std::string pos = field_path("position");
    f_.create_extendible<std::int64_t>(pos + "/step", {}, frame_step_chunk);
    f_.create_extendible<double>(pos + "/time", {}, frame_step_chunk);
    f_.set_attr(pos + "/step", "unit", "1");
    f_.set_attr(pos + "/time", "unit", "s");
    for (auto& name : fields_) {
        const auto& fi = field_info(name);
        const std::string g = field_path(name);
        h5::dims_t inner{n_};
        if (fi.components == 3)
            inner.push_back(3);
        f_.create_extendible<double>(g + "/value", inner, 1, deflate);
        f_.set_attr(g + "/value", "unit", fi.unit);
        if (name != "position") {
            f_.hard_link(pos + "/step", g + "/step");
            f_.hard_link(pos + "/time", g + "/time");
        }
    }
    f_.flush();
}

void FrameWriter::write(std::int64_t step, double time,
                        const std::map<std::string, std::span<const double>>& data) {
    for (auto& name : fields_) {
        auto it = data.find(name);
        if (it == data.end())
            throw InternalError("frame field '" + name + "' not provided");
        const auto& fi = field_info(name);
        if (it->second.size() != n_ * static_cast<std::size_t>(fi.components))
            throw InternalError("frame field '" + name + "' has the wrong size");
        if (runs_.empty())
            f_.append<double>(field_path(name) + "/value", it->second, 1);
        else
            f_.append_runs<double>(field_path(name) + "/value", it->second, runs_);
    }
    const std::string pos = field_path("position");
    f_.append<std::int64_t>(pos + "/step", std::span<const std::int64_t>(&step, 1), 1);
    f_.append<double>(pos + "/time", std::span<const double>(&time, 1), 1);
    f_.flush();
    ++frames_;
}

void FrameWriter::flag_failed(std::int64_t step, const std::string& failure) {
    f_.set_attr(path::particles, "failed_step", step);
    f_.set_attr(path::particles, "failure", failure);
    f_.flush();
}

FrameReader::FrameReader(const h5::File& f)
    : f_(f) {
    const std::string pos = field_path("position");
    if (!f_.exists(pos + "/value"))
        throw SchemaError(f_.name(), pos + "/value",
                          "missing: the file has no frames (run pd-solve)");
    steps_ = f_.read<std::int64_t>(pos + "/step");
    times_ = f_.read<double>(pos + "/time");
    auto sh = f_.shape(pos + "/value");
    if (sh.size() != 3 || sh[2] != 3)
        throw SchemaError(f_.name(), pos + "/value", "expected shape (frames, nodes, 3)");
    if (sh[0] < steps_.size() || times_.size() != steps_.size())
        throw SchemaError(f_.name(), pos + "/step",
                          fmt::format("{} steps, {} times, {} frames of values", steps_.size(),
                                      times_.size(), sh[0]));
    n_ = sh[1];
    for (std::size_t k = 0; k < times_.size(); ++k)
        if (!std::isfinite(times_[k]) || steps_[k] < 0)
            throw SchemaError(f_.name(), pos + "/time",
                              fmt::format("frame {}: step {}, time {}", k, steps_[k], times_[k]));
}

std::vector<std::string> FrameReader::fields() const {
    std::vector<std::string> out;
    for (const auto& fi : frame_fields())
        if (f_.exists(field_path(fi.name) + "/value"))
            out.push_back(fi.name);
    return out;
}

int FrameReader::components(const std::string& field) const {
    return field_info(field).components;
}

std::string FrameReader::unit(const std::string& field) const {
    const std::string p = field_path(field) + "/value";
    return f_.has_attr(p, "unit") ? f_.attr_string(p, "unit") : field_info(field).unit;
}

std::vector<double> FrameReader::read(const std::string& field, std::size_t k) const {
    const std::string p = field_path(field) + "/value";
    auto v = f_.read_rows<double>(p, k, 1);
    if (v.size() != n_ * static_cast<std::size_t>(components(field)))
        throw SchemaError(f_.name(), p, "has the wrong number of nodes");
    const auto c = static_cast<std::size_t>(components(field));
    // Not finite, or beyond any physical value (1e100 in SI units): a damaged frame (4 KiB of
    // random bytes make doubles of random exponent, a third of them above 1e100).
    for (std::size_t i = 0; i < v.size(); ++i)
        if (!(std::fabs(v[i]) <= 1e100))
            throw SchemaError(f_.name(), p,
                              fmt::format("frame {} (step {}): node {} is {} (damaged file?)", k,
                                          k < steps_.size() ? steps_[k] : -1, i / c,
                                          std::isfinite(v[i]) ? fmt::format("{:g}", v[i])
                                                              : std::string("not finite")));
    return v;
}

ObservableWriter::ObservableWriter(h5::File& f, std::size_t num_walls,
                                   std::vector<std::int32_t> bodies)
    : f_(f)
    , walls_(num_walls)
    , bodies_(std::move(bodies)) {}

void ObservableWriter::add(std::int64_t step, double time, std::span<const double> values) {
    steps_.push_back(step);
    times_.push_back(time);
    values_.insert(values_.end(), values.begin(), values.end());
}

namespace {

/// One series of /observables: its name, the shape of a row's value, unit, values per row.
struct Column {
    std::string name;
    h5::dims_t inner;
    std::string unit;
    std::size_t width;
};

/// The series in row order: the standard list, then the wall series (3 * walls values per row
/// each), then the body series (3 * bodies).
std::vector<Column> observable_columns(std::size_t walls, std::size_t bodies) {
    std::vector<Column> cols;
    for (const auto& o : observable_list())
        cols.push_back({o.name, o.components == 3 ? h5::dims_t{3} : h5::dims_t{}, o.unit,
                        static_cast<std::size_t>(o.components)});
    if (walls > 0) {
        cols.push_back({"wall_force", {walls, 3}, "N", 3 * walls});
        cols.push_back({"wall_moment", {walls, 3}, "N m", 3 * walls});
    }
    if (bodies > 0) {
        cols.push_back({"body_force", {bodies, 3}, "N", 3 * bodies});
        cols.push_back({"body_moment", {bodies, 3}, "N m", 3 * bodies});
    }
    return cols;
}

/// A fresh /observables: every series, step and time shared by hard links, the body ids.
void create_series(h5::File& f, const std::vector<Column>& cols,
                   const std::vector<std::int32_t>& bodies) {
    const std::string first = O + "/" + cols.front().name;
    f.create_extendible<std::int64_t>(first + "/step", {}, observable_chunk);
    f.create_extendible<double>(first + "/time", {}, observable_chunk);
    f.set_attr(first + "/step", "unit", "1");
    f.set_attr(first + "/time", "unit", "s");
    for (const auto& c : cols) {
        const std::string g = O + "/" + c.name;
        f.create_extendible<double>(g + "/value", c.inner, observable_chunk);
        f.set_attr(g + "/value", "unit", c.unit);
        if (g != first) {
            f.hard_link(first + "/step", g + "/step");
            f.hard_link(first + "/time", g + "/time");
        }
    }
    if (!bodies.empty()) {
        f.write<std::int32_t>(O + "/body_force/body", bodies, {bodies.size()});
        f.set_attr(O + "/body_force/body", "unit", "1");
        raise_version(f); // pd-file 1.2.0 objects
        f.hard_link(O + "/body_force/body", O + "/body_moment/body");
    }
}

/// A series this pd-solve records that a file from an older one lacks (a restart): created
/// and filled with NaN up to the rows already there (pd-file 1.2 added the dissipation series).
void add_missing_series(h5::File& f, const std::vector<Column>& cols) {
    const std::string first = O + "/" + cols.front().name;
    for (const auto& c : cols) {
        const std::string g = O + "/" + c.name;
        if (f.exists(g + "/value"))
            continue;
        const auto have = f.shape(first + "/step").at(0);
        f.create_extendible<double>(g + "/value", c.inner, observable_chunk);
        f.set_attr(g + "/value", "unit", c.unit);
        f.hard_link(first + "/step", g + "/step");
        f.hard_link(first + "/time", g + "/time");
        if (have > 0)
            f.append<double>(
                g + "/value",
                std::vector<double>(have * c.width, std::numeric_limits<double>::quiet_NaN()),
                have);
    }
}

/// Appends the buffered rows (values row-major, the columns side by side) to every series.
void append_rows(h5::File& f, const std::vector<Column>& cols,
                 const std::vector<std::int64_t>& steps, const std::vector<double>& times,
                 const std::vector<double>& values) {
    const std::size_t rows = steps.size();
    std::size_t width = 0;
    for (const auto& c : cols)
        width += c.width;
    if (values.size() != rows * width)
        throw InternalError("observable rows have the wrong width");
    std::size_t col = 0;
    std::vector<double> v;
    for (const auto& c : cols) {
        v.clear();
        v.reserve(rows * c.width);
        for (std::size_t r = 0; r < rows; ++r)
            for (std::size_t k = 0; k < c.width; ++k)
                v.push_back(values[r * width + col + k]);
        f.append<double>(O + "/" + c.name + "/value", v, rows);
        col += c.width;
    }
    const std::string first = O + "/" + cols.front().name;
    f.append<std::int64_t>(first + "/step", steps, rows);
    f.append<double>(first + "/time", times, rows);
}

} // namespace

std::uint64_t FrameWriter::frame_bytes() const {
    std::uint64_t per_node = 0;
    for (const auto& name : fields_)
        for (const auto& info : frame_fields())
            if (info.name == name)
                per_node += static_cast<std::uint64_t>(info.components);
    return 8 * per_node * n_ + 2 * 8 * frame_step_chunk;
}

std::uint64_t ObservableWriter::flush_bytes() const {
    if (steps_.empty())
        return 0;
    const std::uint64_t per_row = values_.size() / steps_.size() + 2; // and step, time
    return 8 * per_row * (steps_.size() + observable_chunk);
}

void ObservableWriter::flush() {
    const auto cols = observable_columns(walls_, bodies_.size());
    if (!f_.exists(O + "/" + cols.front().name + "/value"))
        create_series(f_, cols, bodies_);
    add_missing_series(f_, cols);
    if (steps_.empty())
        return;
    append_rows(f_, cols, steps_, times_, values_);
    steps_.clear();
    times_.clear();
    values_.clear();
    f_.flush();
}

std::map<std::string, Series> read_observables(const h5::File& f) {
    std::map<std::string, Series> out;
    if (!f.exists(O))
        return out;
    for (const auto& name : f.list(O)) {
        const std::string g = O + "/" + name;
        if (!f.exists(g + "/value"))
            continue;
        Series s;
        h5::dims_t d;
        s.value = f.read<double>(g + "/value", &d);
        s.components = 1;
        for (std::size_t k = 1; k < d.size(); ++k)
            s.components *= static_cast<int>(d[k]);
        s.step = f.read<std::int64_t>(g + "/step");
        s.time = f.read<double>(g + "/time");
        s.unit = f.has_attr(g + "/value", "unit") ? f.attr_string(g + "/value", "unit") : "";
        if (s.step.size() != d[0] || s.time.size() != d[0])
            throw SchemaError(f.name(), g, "step, time and value lengths differ");
        out.emplace(name, std::move(s));
    }
    return out;
}

std::vector<std::int32_t> read_reaction_bodies(const h5::File& f) {
    const std::string p = O + "/body_force/body";
    if (!f.exists(p))
        return {};
    return f.read<std::int32_t>(p);
}

void allocate_for_parallel_append(h5::File& f) {
    // The time series of /particles/nodes and /observables: each group's `value`, and the
    // `step`/`time` of the group that owns them (the others hold hard links to those).
    auto convert = [&](const std::string& root, const std::string& owner) {
        if (!f.exists(root) || !f.exists(owner + "/step"))
            return;
        bool owner_converted = false;
        for (const char* st : {"/step", "/time"})
            if (f.exists(owner + st) && !f.allocated_early(owner + st)) {
                f.reallocate_early(owner + st);
                owner_converted = true;
            }
        for (const auto& g : f.list(root)) {
            const std::string gp = root + "/" + g;
            if (!f.is_group(gp))
                continue;
            if (f.exists(gp + "/value") && !f.is_group(gp + "/value") &&
                !f.allocated_early(gp + "/value"))
                f.reallocate_early(gp + "/value");
            if (owner_converted && gp != owner)
                for (const char* st : {"/step", "/time"})
                    if (f.exists(gp + st)) {
                        f.remove(gp + st);
                        f.hard_link(owner + st, gp + st);
                    }
        }
    };
    convert(P, field_path("position"));
    convert(O, O + "/" + observable_list().front().name);
}

void truncate_after(h5::File& f, std::int64_t step) {
    // A run restarted under MPI-IO appends to these series: a serial run's file (pd-file before
    // 1.2.1) has them allocated late, which MPI-IO cannot extend (issue 13).
    allocate_for_parallel_append(f);
    auto cut = [&](const std::string& owner, const std::vector<std::string>& values) {
        if (!f.exists(owner + "/step"))
            return;
        auto steps = f.read<std::int64_t>(owner + "/step");
        auto keep = static_cast<std::uint64_t>(std::upper_bound(steps.begin(), steps.end(), step) -
                                               steps.begin());
        // Every series is cut to `keep`, not only when `step` is longer: a process killed while
        // it appended a row (values first, then step, then time) leaves series of different
        // lengths, with step possibly not yet past the checkpoint. The rows up to the checkpoint
        // are complete in every series (the checkpoint is written after the flush).
        auto cut_to_keep = [&](const std::string& p) {
            if (f.exists(p) && f.shape(p).at(0) != keep)
                f.resize_rows(p, keep);
        };
        cut_to_keep(owner + "/step");
        cut_to_keep(owner + "/time");
        for (const auto& v : values)
            cut_to_keep(v);
    };
    std::vector<std::string> fv;
    for (const auto& fi : frame_fields())
        fv.push_back(field_path(fi.name) + "/value");
    cut(field_path("position"), fv);
    // A failed run's flagged last frame is gone with the frames after the checkpoint.
    if (f.exists(path::particles) && f.has_attr(path::particles, "failed_step")) {
        f.set_attr(path::particles, "failed_step", std::int64_t{-1});
        f.set_attr(path::particles, "failure", std::string{"none"});
    }
    std::vector<std::string> ov;
    for (const auto& o : observable_list())
        ov.push_back(O + "/" + o.name + "/value");
    ov.push_back(O + "/wall_force/value");
    ov.push_back(O + "/wall_moment/value");
    ov.push_back(O + "/body_force/value");
    ov.push_back(O + "/body_moment/value");
    cut(O + "/" + observable_list().front().name, ov);
}

} // namespace pd::store
