// SPDX-License-Identifier: MIT
// pdgrain._core: the library in the Python process (pybind11). pack() and the solver's run held
// open (pipeline::Simulation) with numpy views of its state; pdgrain/__init__.py adds the
// Pythonic front (scene dicts, the scene builder, run(until=)). The rules of the views:
// - positions, displacements, forces, body: read-only views (no copy) into the solver's state,
//   (n, 3) float64 or (n,) int32, valid while the Simulation is open; they follow the run.
// - velocities: a writable view; a write takes effect at the next step (the integrator's next
//   half kick). Components a displacement condition prescribes and nodes of fixed bodies are
//   set by the solver at every step whatever is written. Checkpoints store what was written.
// - bond_alive: a writable (B,) uint8 view of the CSR bond states (1 intact, 0 broken); prefer
//   break_bonds(), which cuts both ends of a bond. Bonds broken from Python count as damage and
//   in frames and checkpoints, not in the broken-bond observable or the fracture energy.
// - damage: a copy, computed when read.
// - conditions: the scene's displacement and force conditions (value = amplitude T(t) S(X) on
//   their nodes' components). Writable: amplitude, time_function (not to or from rotation; the
//   force-only staircases not on a displacement), time_parameters, space_parameter. A write to
//   a displacement condition applies at once at the current time: the prescribed components
//   take the u and v the new settings give, and the kinetic energy this changes is counted as
//   external work (the driver's), so the energy balance holds; the solver then evaluates the
//   new settings at every step. A write that changes the value at the current time makes the
//   nodes jump, and the elastic energy of the jump is not counted (the forces are those of the
//   old positions until the next step): hold() keeps the value (time function constant).
//   Not writable: nodes, components, kind (set up once). Writes live in the process: the file
//   keeps the packed conditions, so `pd-solve --restart` continues with those. Collective.
// Under MPI (mpirun -np N python3 ...) every rank holds all n nodes; only its own rows (the
// `rows` array) are current, the others are its ghosts or stale.
#include "core/errors.hpp"
#include "core/mpi.hpp"
#include "core/tool.hpp"
#include "core/version.hpp"
#include "model/functions.hpp"
#include "model/model.hpp"
#include "model/slots.hpp"
#include "pipeline/pack.hpp"
#include "pipeline/simulation.hpp"
#include "pipeline/solve.hpp"
#include "solver/observables.hpp"
#include "solver/solver.hpp"

#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <string>
#include <vector>
#ifdef _OPENMP
#include <omp.h>
#endif

namespace py = pybind11;

namespace {

/// The MPI session of the process: opened at import (MPI_Init under mpirun unless mpi4py did it),
/// closed at exit.
std::unique_ptr<pd::mpi::Session>& session() {
    static std::unique_ptr<pd::mpi::Session> s;
    return s;
}

pd::Context make_context(const std::string& what, bool quiet, bool verbose) {
    const int rank = session() ? session()->rank() : 0;
    const int size = session() ? session()->size() : 1;
    const auto v = quiet     ? pd::Verbosity::quiet
                   : verbose ? pd::Verbosity::debug
                             : pd::Verbosity::normal;
    pd::Context ctx{pd::Log("pdgrain", rank, v), {}, rank, size, {}};
    ctx.run.tool = "pdgrain-python";
    ctx.run.version = pd::version;
    ctx.run.git_commit = pd::git_commit;
    ctx.run.command_line = "python: " + what;
    ctx.run.start_time = pd::utc_now();
    ctx.run.mpi_ranks = size;
#ifdef _OPENMP
    ctx.run.threads = omp_get_max_threads();
#endif
    return ctx;
}

/// The provenance record of a library call that owns a file (pack, a run).
void record(pd::Context& ctx, int code) {
    if (!ctx.on_exit)
        return;
    auto hook = std::move(ctx.on_exit);
    ctx.on_exit = nullptr;
    hook(code);
}

int code_of(const std::exception& e) {
    if (dynamic_cast<const pd::InputError*>(&e))
        return pd::exit_input;
    if (dynamic_cast<const pd::NumericalError*>(&e))
        return pd::exit_numerical;
    return pd::exit_internal;
}

void pack(const std::string& scene, const std::string& output, const std::vector<std::string>& sets,
          bool quiet, bool overwrite) {
    pd::pipeline::PackOptions opt;
    opt.scene = scene;
    opt.output = output;
    opt.sets = sets;
    opt.overwrite = overwrite;
    auto ctx = make_context("pack " + scene + " -> " + output, quiet, false);
    try {
        pd::pipeline::pack(opt, ctx);
    } catch (const std::exception& e) {
        record(ctx, code_of(e));
        throw;
    }
    record(ctx, pd::exit_ok);
}

/// A view of `n` x `comp` values of `v` (no copy) whose base keeps `owner` alive.
template <class T>
py::array view(std::vector<T>& v, std::size_t comp, py::handle owner, bool writable) {
    const std::size_t n = comp ? v.size() / comp : v.size();
    py::array a = comp ? py::array_t<T>({n, comp}, {comp * sizeof(T), sizeof(T)}, v.data(), owner)
                       : py::array_t<T>({n}, {sizeof(T)}, v.data(), owner);
    if (!writable)
        a.attr("setflags")(py::arg("write") = false);
    return a;
}

class Simulation {
  public:
    Simulation(const std::string& file, int threads, bool restart, bool overwrite,
               std::optional<double> final_time, std::optional<std::int64_t> max_steps,
               double energy_tolerance, bool penetration_check, bool force_dt, bool quiet,
               bool verbose)
        : ctx_(make_context("Simulation(" + file + ")", quiet, verbose)) {
#ifdef _OPENMP
        if (threads > 0)
            omp_set_num_threads(threads);
        ctx_.run.threads = omp_get_max_threads();
#else
        (void)threads;
#endif
        pd::pipeline::SolveOptions opt;
        opt.file = file;
        opt.restart = restart;
        opt.overwrite = overwrite;
        if (final_time) {
            opt.final_time = *final_time;
            opt.final_time_given = true;
        }
        if (max_steps) {
            opt.max_steps = *max_steps;
            opt.max_steps_given = true;
        }
        opt.energy_tolerance = energy_tolerance;
        opt.penetration_check = penetration_check;
        opt.force_dt = force_dt;
        opt.checkpoint_wall_seconds = 0; // the driver decides (checkpoint(), close())
        opt.progress_seconds = 1e30;     // no progress lines between the driver's calls
        try {
            sim_ = std::make_unique<pd::pipeline::Simulation>(opt, ctx_);
            open_ = true;
        } catch (const std::exception& e) {
            record(ctx_, code_of(e));
            throw;
        }
    }
    ~Simulation() {
        try {
            close();
        } catch (const std::exception&) {
        }
    }

    std::int64_t step(std::int64_t n) {
        check_open();
        try {
            py::gil_scoped_release nogil;
            return sim_->advance(n);
        } catch (const std::exception& e) {
            fail(e);
            throw;
        }
    }
    void checkpoint() {
        check_open();
        try {
            sim_->checkpoint();
        } catch (const std::exception& e) {
            fail(e);
            throw;
        }
    }
    int close() {
        if (!open_)
            return code_;
        try {
            code_ = sim_->close();
        } catch (const std::exception& e) {
            fail(e);
            throw;
        }
        open_ = false; // the state stays: views taken before remain valid
        record(ctx_, code_);
        return code_;
    }

    pd::solver::Solver& s() {
        check_open();
        return sim_->solver();
    }
    const pd::pipeline::Simulation& sim() const {
        check_open();
        return *sim_;
    }
    pd::model::Model& model() {
        check_open();
        return sim_->model();
    }
    bool is_open() const {
        return open_;
    }

    py::dict observe() {
        const auto o = s().observe();
        py::dict d;
        d["kinetic_energy"] = o.kinetic_energy;
        d["elastic_energy"] = o.elastic_energy;
        d["contact_energy"] = o.contact_energy;
        d["external_work"] = o.external_work;
        d["momentum"] = std::vector<double>(o.momentum, o.momentum + 3);
        d["contact_count"] = o.contact_count;
        d["broken_bonds"] = o.broken_bonds;
        d["fracture_energy"] = o.fracture_energy;
        d["damping_dissipation"] = o.damping_dissipation;
        d["friction_dissipation"] = o.friction_dissipation;
        d["viscous_dissipation"] = o.viscous_dissipation;
        d["gravity_potential"] = o.gravity_potential;
        d["wall_force"] = o.wall_force;
        d["body_force"] = o.body_force;
        return d;
    }

    /// Cuts the intact bonds whose mask entry is true, with their other ends; returns the pairs.
    std::int64_t break_mask(const py::array_t<bool, py::array::c_style | py::array::forcecast>& m) {
        auto& b = s().bonds();
        if (static_cast<std::size_t>(m.size()) != b.alive.size())
            throw pd::InputError(fmt::format("break_bonds: the mask has {} entries, there are {} "
                                             "bonds (bond_alive)",
                                             m.size(), b.alive.size()));
        const bool* cut = m.data();
        return cut_where(
            [&](std::size_t k, pd::model::index_t, pd::model::index_t) { return cut[k]; });
    }
    /// Cuts the bonds crossing the segment p0-p1 in the xy plane at the current positions.
    std::int64_t break_segment(const std::array<double, 3>& p0, const std::array<double, 3>& p1) {
        const auto& x = s().state().x;
        return cut_where([&](std::size_t, pd::model::index_t i, pd::model::index_t j) {
            return pd::model::segments_cross(&x[3 * static_cast<std::size_t>(i)],
                                             &x[3 * static_cast<std::size_t>(j)], p0.data(),
                                             p1.data());
        });
    }

    /// (i, j) of every bond of this rank's rows, global node ids, in bond_alive's order.
    py::tuple bond_ends() {
        const auto& st = s().state();
        const auto& b = s().bonds();
        py::array_t<std::int64_t> i(static_cast<py::ssize_t>(b.neighbor.size()));
        py::array_t<std::int64_t> j(static_cast<py::ssize_t>(b.neighbor.size()));
        auto pi = i.mutable_unchecked<1>();
        auto pj = j.mutable_unchecked<1>();
        for (std::size_t a = 0; a < st.rows.size(); ++a)
            for (auto k = b.offsets[a]; k < b.offsets[a + 1]; ++k) {
                pi(k) = st.rows[a];
                pj(k) = b.neighbor[static_cast<std::size_t>(k)];
            }
        return py::make_tuple(i, j);
    }

  private:
    template <class Cut>
    std::int64_t cut_where(Cut cut) {
        const auto& st = s().state();
        auto& b = s().bonds();
        // Both ends: the row of j may be on this rank (one rank: always) or another one, whose
        // own call cuts it (a symmetric rule gives the same answer there).
        std::vector<std::pair<std::size_t, pd::model::index_t>> hit; // bond, its node i
        for (std::size_t a = 0; a < st.rows.size(); ++a)
            for (auto k = b.offsets[a]; k < b.offsets[a + 1]; ++k) {
                const auto kk = static_cast<std::size_t>(k);
                if (b.alive[kk] && cut(kk, st.rows[a], b.neighbor[kk]))
                    hit.emplace_back(kk, st.rows[a]);
            }
        std::vector<std::int64_t> row_of(st.n, -1);
        for (std::size_t a = 0; a < st.rows.size(); ++a)
            row_of[static_cast<std::size_t>(st.rows[a])] = static_cast<std::int64_t>(a);
        std::int64_t pairs = 0;
        for (const auto& [k, i] : hit) {
            if (!b.alive[k])
                continue; // cut already as the other end of an earlier one
            b.alive[k] = 0;
            ++pairs;
            const auto ra = row_of[static_cast<std::size_t>(b.neighbor[k])];
            if (ra < 0)
                continue;
            const auto r = static_cast<std::size_t>(ra);
            for (auto q = b.offsets[r]; q < b.offsets[r + 1]; ++q)
                if (b.neighbor[static_cast<std::size_t>(q)] == i)
                    b.alive[static_cast<std::size_t>(q)] = 0;
        }
        return pairs;
    }

    void check_open() const {
        if (!open_)
            throw std::runtime_error("pdgrain.Simulation: the run is closed");
    }
    /// An error ends the run as it ends pd-solve: the file closed, its provenance recorded.
    void fail(const std::exception& e) {
        code_ = code_of(e);
        open_ = false;
        sim_->abandon();
        record(ctx_, code_);
    }

    pd::Context ctx_;
    std::unique_ptr<pd::pipeline::Simulation> sim_;
    bool open_ = false;
    int code_ = pd::exit_ok;
};

constexpr std::array<const char*, 7> time_fn_names{
    "constant", "linear", "quadratic", "sine", "rotation", "linear_step", "linear_slow_fast"};

/// One loading condition of an open run, by index (the rules: the file's head comment).
class Condition {
  public:
    Condition(py::object owner, std::size_t k)
        : owner_(std::move(owner))
        , k_(k) {}

    pd::model::NodeCondition& c() const {
        return owner_.cast<Simulation&>().model().loading.conditions.at(k_);
    }
    std::string kind() const { return c().is_force ? "force" : "displacement"; }
    std::string components() const {
        std::string s;
        for (int d = 0; d < 3; ++d)
            if (c().dofs & (1u << d))
                s += "xyz"[d];
        return s;
    }
    std::string time_function() const { return time_fn_names.at(static_cast<int>(c().time_fn)); }
    void set_time_function(const std::string& name) {
        auto& cond = c();
        std::size_t k = 0;
        while (k < time_fn_names.size() && name != time_fn_names[k])
            ++k;
        const auto fn = static_cast<pd::model::TimeFn>(k);
        if (k == time_fn_names.size())
            throw pd::InputError(
                fmt::format("condition '{}': no time function '{}'", cond.name, name));
        if ((fn == pd::model::TimeFn::rotation) != (cond.time_fn == pd::model::TimeFn::rotation))
            throw pd::InputError(fmt::format("condition '{}': a rotation stays a rotation and "
                                             "nothing else becomes one (its centre, its two "
                                             "components are set up at packing)",
                                             cond.name));
        if (!cond.is_force &&
            (fn == pd::model::TimeFn::linear_step || fn == pd::model::TimeFn::linear_slow_fast))
            throw pd::InputError(
                fmt::format("condition '{}': '{}' is for force conditions only", cond.name, name));
        write([&](pd::model::NodeCondition& w) { w.time_fn = fn; });
    }
    double amplitude() const { return c().amplitude; }
    void set_amplitude(double a) {
        finite(a, "amplitude");
        write([&](pd::model::NodeCondition& w) { w.amplitude = a; });
    }
    std::array<double, 3> time_parameters() const {
        return {c().params[1], c().params[2], c().params[3]};
    }
    void set_time_parameters(const std::array<double, 3>& p) {
        for (double v : p)
            finite(v, "time_parameters");
        write([&](pd::model::NodeCondition& w) { std::copy(p.begin(), p.end(), &w.params[1]); });
    }
    double space_parameter() const { return c().params[0]; }
    void set_space_parameter(double p) {
        finite(p, "space_parameter");
        write([&](pd::model::NodeCondition& w) { w.params[0] = p; });
    }
    /// amplitude T(t) (the value where S(X) = 1) at time t.
    double value(double t) const {
        double rate = 0;
        return c().amplitude * pd::model::time_function(c().time_fn, c().params, t, &rate);
    }
    /// Keeps the value of the current time from now on (time function constant).
    void hold() {
        auto& cond = c();
        if (cond.time_fn == pd::model::TimeFn::rotation)
            throw pd::InputError(
                fmt::format("condition '{}': a rotation cannot be held", cond.name));
        const double a = value(owner_.cast<Simulation&>().s().state().time);
        write([&](pd::model::NodeCondition& w) {
            w.amplitude = a;
            w.time_fn = pd::model::TimeFn::constant;
        });
    }
    py::array nodes() const {
        auto& n = c().nodes;
        return view(n, 0, owner_, false);
    }

  private:
    /// Changes the condition and applies it at the current time at once: the prescribed
    /// components take the new settings' u and v; the kinetic energy this changes on this
    /// rank's rows counts as external work (the driver's) and the external power of the step's
    /// start is that of the new velocities (solver/detail.hpp node_power(): gravity and the
    /// reaction, not a force condition on the same component), so the energy balance holds.
    template <class Change>
    void write(Change change) {
        auto& s = owner_.cast<Simulation&>().s();
        auto& st = s.state();
        std::vector<double> v0 = st.v;
        change(c());
        if (c().is_force)
            return;
        s.apply_displacements();
        const auto& g = owner_.cast<Simulation&>().model().loading.gravity;
        std::vector<std::uint8_t> own(st.n, 0);
        for (auto i : st.rows)
            own[static_cast<std::size_t>(i)] = 1;
        double dke = 0, dp = 0;
        for (auto n : c().nodes) {
            const auto i = static_cast<std::size_t>(n);
            for (std::size_t d = 0; own[i] && d < 3; ++d) {
                const double a = v0[3 * i + d], b = st.v[3 * i + d];
                dke += 0.5 * st.rho[i] * st.vol[i] * (b * b - a * a);
                if (st.moving[i])
                    dp += st.vol[i] * (st.rho[i] * g[d] - st.f[3 * i + d]) * (b - a);
            }
        }
        s.set_external_work(s.external_work() + dke, s.external_power_last() + dp);
    }
    double finite(double v, const char* what) const {
        if (!std::isfinite(v))
            throw pd::InputError(fmt::format("condition '{}': {} must be finite", c().name, what));
        return v;
    }
    py::object owner_; ///< the Simulation (kept alive)
    std::size_t k_;
};

void bind_condition(py::module_& mod) {
    py::class_<Condition>(mod, "Condition")
        .def_property_readonly("name", [](const Condition& c) { return c.c().name; })
        .def_property_readonly("kind", &Condition::kind)
        .def_property_readonly("components", &Condition::components)
        .def_property_readonly("nodes", &Condition::nodes)
        .def_property("amplitude", &Condition::amplitude, &Condition::set_amplitude)
        .def_property("time_function", &Condition::time_function, &Condition::set_time_function)
        .def_property("time_parameters", &Condition::time_parameters,
                      &Condition::set_time_parameters)
        .def_property("space_parameter", &Condition::space_parameter,
                      &Condition::set_space_parameter)
        .def("value", &Condition::value, py::arg("t"), "amplitude T(t): the value where S = 1")
        .def("hold", &Condition::hold, "keep the current value (time function constant)")
        .def("__repr__", [](const Condition& c) {
            return fmt::format("<pdgrain.Condition '{}' {} {} amplitude={} {}>", c.c().name,
                               c.kind(), c.components(), c.amplitude(), c.time_function());
        });
}

/// Simulation's methods and scalar properties.
py::class_<Simulation> bind_simulation(py::module_& mod) {
    return py::class_<Simulation>(mod, "Simulation")
        .def(py::init<const std::string&, int, bool, bool, std::optional<double>,
                      std::optional<std::int64_t>, double, bool, bool, bool, bool>(),
             py::arg("file"), py::arg("threads") = 0, py::arg("restart") = false,
             py::arg("overwrite") = false, py::arg("final_time") = py::none(),
             py::arg("max_steps") = py::none(), py::arg("energy_tolerance") = 0.05,
             py::arg("penetration_check") = true, py::arg("force_dt") = false,
             py::arg("quiet") = true, py::arg("verbose") = false)
        .def("step", &Simulation::step, py::arg("n") = 1,
             "advance at most n steps (not past the last); returns the steps done")
        .def("checkpoint", &Simulation::checkpoint)
        .def("close", &Simulation::close, "end the run; returns the exit code pd-solve would")
        .def("observe", &Simulation::observe)
        .def("bond_ends", &Simulation::bond_ends)
        .def("break_mask", &Simulation::break_mask)
        .def("break_segment", &Simulation::break_segment)
        .def_property_readonly("is_open", &Simulation::is_open)
        .def_property_readonly("finished", [](Simulation& p) { return p.sim().finished(); })
        .def_property_readonly("step_index", [](Simulation& p) { return p.sim().step(); })
        .def_property_readonly("last_step", [](Simulation& p) { return p.sim().steps().last; })
        .def_property_readonly("total_steps", [](Simulation& p) { return p.sim().steps().total; })
        .def_property_readonly("output_every",
                               [](Simulation& p) { return p.sim().steps().out_every; })
        .def_property_readonly("time", [](Simulation& p) { return p.s().state().time; })
        .def_property_readonly("dt", [](Simulation& p) { return p.s().dt(); })
        .def_property_readonly("num_nodes", [](Simulation& p) { return p.s().state().n; });
}

/// Simulation's numpy views and the conditions.
/// A view of one field of the solver's state (comp per node; 0: a flat array).
template <class T>
void state_view(py::class_<Simulation>& cls, const char* name,
                std::vector<T> pd::solver::State::*field, std::size_t comp, bool writable) {
    cls.def_property_readonly(name, [field, comp, writable](py::object self) {
        return view(self.cast<Simulation&>().s().state().*field, comp, self, writable);
    });
}

void bind_views(py::class_<Simulation>& cls) {
    using St = pd::solver::State;
    state_view(cls, "positions", &St::x, 3, false);
    state_view(cls, "reference_positions", &St::x0, 3, false);
    state_view(cls, "displacements", &St::u, 3, false);
    state_view(cls, "velocities", &St::v, 3, true);
    state_view(cls, "forces", &St::f, 3, false);
    state_view(cls, "body", &St::body, 0, false);
    state_view(cls, "rows", &St::rows, 0, false);
    cls.def_property_readonly("bond_alive", [](py::object self) {
        return view(self.cast<Simulation&>().s().bonds().alive, 0, self, true);
    });
    cls.def_property_readonly("damage", [](Simulation& p) {
        std::vector<double> phi;
        p.s().damage(phi);
        return py::array_t<double>(static_cast<py::ssize_t>(phi.size()), phi.data());
    });
    cls.def_property_readonly("conditions", [](py::object self) {
        auto& p = self.cast<Simulation&>();
        py::list out;
        for (std::size_t k = 0; k < p.model().loading.conditions.size(); ++k)
            out.append(Condition(self, k));
        return out;
    });
}

} // namespace

PYBIND11_MODULE(_core, mod) {
    mod.doc() = "pdgrain's library in the Python process (see pdgrain/__init__.py)";
    {
        static int argc = 1;
        static char name[] = "python";
        static char* args[] = {name, nullptr};
        static char** argv = args;
        session() = std::make_unique<pd::mpi::Session>(&argc, &argv);
        py::module_::import("atexit").attr("register")(
            py::cpp_function([]() { session().reset(); }));
    }
    mod.attr("__version__") = pd::version;
    mod.attr("git_commit") = pd::git_commit;
    mod.attr("rank") = session()->rank();
    mod.attr("size") = session()->size();

    static py::exception<pd::InputError> input_error(mod, "InputError", PyExc_ValueError);
    static py::exception<pd::NumericalError> numerical_error(mod, "NumericalError",
                                                             PyExc_RuntimeError);
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p)
                std::rethrow_exception(p);
        } catch (const pd::InputError& e) {
            input_error(e.what());
        } catch (const pd::NumericalError& e) {
            numerical_error(e.what());
        }
    });

    mod.def("pack", &pack, py::arg("scene"), py::arg("output"),
            py::arg("sets") = std::vector<std::string>{}, py::arg("quiet") = true,
            py::arg("overwrite") = false,
            "pd-pack: the scene (JSON path) into the pd-file `output`");

    bind_condition(mod);
    auto cls = bind_simulation(mod);
    bind_views(cls);
}
