// SPDX-License-Identifier: MIT
// libFuzzer harness for the pd-file reader and validator (issue 13). Structure-aware: a small
// valid pd file (two discs, partition, checkpoint) is built once; each input is a list of edits
// (overwrite one element or attribute with an extreme value, resize, delete, retype a string)
// applied to a copy, which is then read as pd-solve and pd-post read it: check_version,
// read_model, read_partition, read_latest_checkpoint, read_observables, and a Solver built and
// initialised from the model. Random bytes inside HDF5's own metadata are not the aim (that
// fuzzes libhdf5); the aim is every value our code takes from a file.
// A pd::Error (exit 2/3) is the right answer; any other exception or a sanitizer report is a
// finding.
#include "core/errors.hpp"
#include "core/log.hpp"
#include "h5/file.hpp"
#include "pipeline/scene.hpp"
#include "solver/solver.hpp"
#include "store/checkpoint_io.hpp"
#include "store/frames.hpp"
#include "store/model_io.hpp"
#include "store/partition_io.hpp"
#include "store/schema.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fuzzer/FuzzedDataProvider.h>
#include <limits>
#include <string>
#include <unistd.h>
#include <vector>

namespace {

namespace fs = std::filesystem;

const char* const seed_scene = R"({
  "dimension": 2,
  "materials": { "m1": { "law": "pmb", "density": 1200, "youngs_modulus": 3.24e7,
                         "fracture_energy": 50 } },
  "discretization": { "mesh_size": 2.5e-4, "horizon_factor": 3 },
  "particles": [
    { "shape": "disc", "radius": 1.0e-3, "center": [-1.15e-3, 0], "material": "m1",
      "velocity": [0.5, 0] },
    { "shape": "disc", "radius": 1.0e-3, "center": [1.15e-3, 0], "material": "m1",
      "velocity": [-0.5, 0] } ],
  "walls": [ { "name": "floor", "type": "plane", "point": [0, -2e-3], "normal": [0, 1] } ],
  "contact": { "radius_factor": 0.95, "stiffness": "auto" },
  "loading": { "gravity": [0, -10] },
  "solver": { "final_time": 1.0e-5, "dt": "auto", "output_interval": 2.0e-6 }
})";

struct Seed {
    fs::path seed, work;
    std::vector<std::string> datasets;                      // every dataset path
    std::vector<std::pair<std::string, std::string>> attrs; // (object path, attribute name)
};

void walk(const pd::h5::File& f, const std::string& g, Seed& s) {
    for (const auto& n : f.attr_names(g.empty() ? "/" : g))
        s.attrs.emplace_back(g.empty() ? "/" : g, n);
    for (const auto& c : f.list(g.empty() ? "/" : g)) {
        const std::string p = g + "/" + c;
        if (f.is_group(p)) {
            walk(f, p, s);
        } else {
            s.datasets.push_back(p);
            for (const auto& n : f.attr_names(p))
                s.attrs.emplace_back(p, n);
        }
    }
}

Seed make_seed() {
    Seed s;
    const fs::path dir = fs::temp_directory_path();
    const std::string pid = std::to_string(::getpid());
    s.seed = dir / ("pd_fuzz_file_seed_" + pid + ".h5");
    s.work = dir / ("pd_fuzz_file_work_" + pid + ".h5");
    const pd::Log log("fuzz_file", 0, pd::Verbosity::quiet);
    const auto m = pd::pipeline::build_scene(seed_scene, "seed.json", log);
    {
        pd::h5::File f(s.seed.string(), pd::h5::Mode::create_truncate);
        pd::store::write_model(f, m);
        pd::store::Partition p;
        p.by = "body";
        p.method = "trivial";
        p.num_parts = 2;
        p.owner = {0, 1};
        pd::store::write_partition(f, p);
        pd::store::Checkpoint c;
        c.step = 10;
        c.dt = 1e-8;
        c.time = 10 * c.dt;
        c.u.assign(3 * m.nodes.num(), 0.0);
        c.v.assign(3 * m.nodes.num(), 0.0);
        c.f.assign(3 * m.nodes.num(), 0.0);
        c.alive.assign(m.bonds.num(), 1);
        pd::store::write_checkpoint(f, c);
    }
    const pd::h5::File f(s.seed.string(), pd::h5::Mode::read);
    walk(f, "", s);
    return s;
}

double special(FuzzedDataProvider& in, double size) {
    static const double table[] = {0.0,
                                   -0.0,
                                   1.0,
                                   -1.0,
                                   0.5,
                                   2.0,
                                   std::numeric_limits<double>::quiet_NaN(),
                                   std::numeric_limits<double>::infinity(),
                                   -std::numeric_limits<double>::infinity(),
                                   1e300,
                                   -1e300,
                                   1e-300,
                                   2147483647.0,
                                   -2147483648.0,
                                   2147483648.0,
                                   1e9,
                                   -1e9,
                                   9.3e18,
                                   -9.3e18};
    const int k = in.ConsumeIntegralInRange<int>(0, 23);
    if (k < 19)
        return table[k];
    if (k == 19)
        return size;
    if (k == 20)
        return size - 1;
    if (k == 21)
        return size + 1;
    if (k == 22)
        return -size;
    return in.ConsumeFloatingPoint<double>();
}

template <class T>
T saturate(double v) {
    if (std::isnan(v))
        return T(0);
    if (v <= static_cast<double>(std::numeric_limits<T>::lowest()))
        return std::numeric_limits<T>::lowest();
    if (v >= static_cast<double>(std::numeric_limits<T>::max()))
        return std::numeric_limits<T>::max();
    return static_cast<T>(v);
}

template <class T>
void edit_dataset(pd::h5::File& f, const std::string& p, int op, FuzzedDataProvider& in) {
    pd::h5::dims_t dims;
    auto v = f.read<T>(p, &dims);
    if (dims.empty())
        dims = {1};
    std::uint64_t inner = 1;
    for (std::size_t d = 1; d < dims.size(); ++d)
        inner *= dims[d];
    if (op == 0 && !v.empty()) { // one element
        const auto k = in.ConsumeIntegralInRange<std::size_t>(0, v.size() - 1);
        if constexpr (std::is_floating_point_v<T>)
            v[k] = static_cast<T>(special(in, double(v.size())));
        else
            v[k] = saturate<T>(special(in, double(v.size())));
    } else if (op == 1) { // fewer or more rows
        const auto rows = in.ConsumeIntegralInRange<std::uint64_t>(0, dims[0] + 3);
        dims[0] = rows;
        v.resize(rows * inner, v.empty() ? T(0) : v.back());
    } else if (op == 2 && !v.empty()) { // every element
        const double x = special(in, double(v.size()));
        for (auto& e : v)
            e = std::is_floating_point_v<T> ? static_cast<T>(x) : saturate<T>(x);
    }
    f.remove(p);
    f.write<T>(p, v, dims);
}

void edit(pd::h5::File& f, const Seed& s, FuzzedDataProvider& in) {
    const int op = in.ConsumeIntegralInRange<int>(0, 5);
    if (op <= 3) {
        const auto& p =
            s.datasets[in.ConsumeIntegralInRange<std::size_t>(0, s.datasets.size() - 1)];
        if (!f.exists(p))
            return;
        if (op == 3) {
            f.remove(p);
            return;
        }
        const char c = f.type_class(p);
        const std::size_t size = f.type_size(p);
        if (c == 'f')
            edit_dataset<double>(f, p, op, in);
        else if (c == 'i' && size == 4)
            edit_dataset<std::int32_t>(f, p, op, in);
        else if (c == 'i')
            edit_dataset<std::int64_t>(f, p, op, in);
        else if (c == 'u')
            edit_dataset<std::uint8_t>(f, p, op, in);
        else if (c == 's') {
            f.remove(p);
            f.write_string(p, in.ConsumeRandomLengthString(32));
        }
        return;
    }
    const auto& [p, name] = s.attrs[in.ConsumeIntegralInRange<std::size_t>(0, s.attrs.size() - 1)];
    if (!f.exists(p) && p != "/")
        return;
    if (op == 5) { // any attribute as a string (a number where one is expected, or a name)
        f.set_attr(p, name, in.ConsumeRandomLengthString(24));
        return;
    }
    std::vector<double> v;
    try {
        v = f.attr_vector<double>(p, name);
    } catch (const pd::Error&) {
        f.set_attr(p, name, in.ConsumeRandomLengthString(24)); // a string attribute
        return;
    }
    if (v.empty())
        return;
    v[in.ConsumeIntegralInRange<std::size_t>(0, v.size() - 1)] = special(in, double(v.size()));
    if (v.size() == 1)
        f.set_attr(p, name, v[0]);
    else
        f.set_attr(p, name, v);
}

void read_as_the_tools_do(const std::string& file) {
    const pd::h5::File f(file, pd::h5::Mode::read);
    pd::store::check_version(f);
    auto m = pd::store::read_model(f);
    if (f.exists(pd::store::path::partition)) {
        const auto by = f.attr_string(pd::store::path::partition, "by");
        (void)pd::store::read_partition(f, by == "node" ? m.nodes.num() : m.bodies.num());
    }
    (void)pd::store::read_latest_checkpoint(f, m.nodes.num(), m.bonds.num());
    (void)pd::store::read_observables(f);
    pd::solver::Solver s(m);
    s.initialize();
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const Seed seed = make_seed();
    FuzzedDataProvider in(data, size);
    fs::copy_file(seed.seed, seed.work, fs::copy_options::overwrite_existing);
    try {
        pd::h5::File f(seed.work.string(), pd::h5::Mode::read_write);
        const int edits = in.ConsumeIntegralInRange<int>(1, 4);
        for (int e = 0; e < edits && in.remaining_bytes() > 0; ++e)
            edit(f, seed, in);
    } catch (const pd::Error&) {
        return 0; // an edit HDF5 refused (e.g. a type it cannot convert): not a case
    }
    try {
        read_as_the_tools_do(seed.work.string());
    } catch (const pd::Error&) {
        // exit 2 or 3 with a message: the right answer
    } catch (const std::exception& e) {
        std::fprintf(stderr, "fuzz_file: exception outside pd::Error (a tool's exit 4): %s\n",
                     e.what());
        std::abort();
    }
    return 0;
}
