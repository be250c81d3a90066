// tsubu._core: the Python binding of a run (docs/python.md). A Simulation holds a Session
// (session.hpp); this file adds the NumPy arrays over its particles, the contact list, the
// analyses, the GIL released while stepping, Ctrl-C between steps, and the engine's errors as
// Python exceptions.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <type_traits>
#include <vector>

#include "session.hpp"
#include "tsubu/analysis/measures.hpp"
#include "tsubu/analysis/results.hpp"
#include "tsubu/app/checkpoint.hpp"
#include "tsubu/core/error.hpp"
#include "tsubu/version.hpp"

namespace py = pybind11;

namespace tsubu::python {
namespace {

// The Python object: a session and whether it is stepping (read and written with the GIL
// held only, so no lock is needed). While it steps, with the GIL released, other Python
// threads may not touch its state.
struct PySimulation {
  explicit PySimulation(Session s) : session(std::move(s)) {}
  Session session;
  bool stepping = false;

  Session& idle() {
    if (stepping) throw std::runtime_error("the simulation is stepping in another thread; wait for it to return");
    return session;
  }
};

// A Python value as the text of a TOML value: bool, int, float (repr round-trips), str (a
// TOML string), and lists or tuples of these.
std::string toml_value(py::handle v) {
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>() ? "true" : "false";
  const auto value = py::reinterpret_borrow<py::object>(v);
  if (py::isinstance<py::int_>(v)) return py::repr(py::int_(value)).cast<std::string>();
  if (py::isinstance<py::float_>(v)) return py::repr(py::float_(value)).cast<std::string>();  // NumPy's float64 too
  if (py::isinstance<py::str>(v))
    return py::module_::import("json").attr("dumps")(v, py::arg("ensure_ascii") = false).cast<std::string>();
  if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v) || py::isinstance<py::array>(v)) {
    std::string out = "[";
    for (py::handle item : py::iter(v)) out += (out.size() > 1 ? ", " : "") + toml_value(item);
    return out + "]";
  }
  if (py::hasattr(v, "item")) return toml_value(v.attr("item")());  // NumPy scalars
  throw py::type_error("cannot give " + py::repr(v).cast<std::string>() +
                       " as a TOML value: use bool, int, float, str or a list of them");
}

// overrides: {"key.path": value} (values as Python values) or ["key.path=value", ...] (the
// command line's --set text, TOML values as written there).
std::vector<std::string> override_texts(const py::object& overrides) {
  std::vector<std::string> sets;
  if (overrides.is_none()) return sets;
  if (py::isinstance<py::dict>(overrides)) {
    for (auto [key, value] : overrides.cast<py::dict>()) sets.push_back(py::str(key).cast<std::string>() + "=" + toml_value(value));
    return sets;
  }
  for (py::handle set : py::iter(overrides)) sets.push_back(set.cast<std::string>());
  return sets;
}

// A scenario file (str or os.PathLike) or the text of one (a str with a line break).
Scenario scenario_from(const py::object& source, const py::object& overrides) {
  const std::vector<std::string> sets = override_texts(overrides);
  if (py::isinstance<py::str>(source)) {
    const std::string text = source.cast<std::string>();
    if (text.find('\n') != std::string::npos) return load_scenario_text(text, "<scenario text>", sets);
  }
  const std::string path = py::str(py::module_::import("os").attr("fspath")(source)).cast<std::string>();
  return load_scenario(path, sets);
}

void make_read_only(py::array& a) { py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_; }

// A per-particle array as NumPy: shape (n,) or, for Vec3, (n, 3) float64. A view into the
// particle store kept alive by `owner` while the storage cannot move (no inflow, no open face; spatial
// sorting permutes in place), else a copy; copies are read-only, views writable if asked.
template <class T>
py::array particle_array(PySimulation& self, py::handle owner, std::vector<T>& v, bool writable) {
  constexpr bool vec3 = std::is_same_v<T, Vec3>;
  using Scalar = std::conditional_t<vec3, double, T>;
  std::vector<py::ssize_t> shape{static_cast<py::ssize_t>(v.size())}, strides{sizeof(T)};
  if constexpr (vec3) shape.push_back(3), strides.push_back(sizeof(double));
  auto* data = reinterpret_cast<Scalar*>(v.data());
  const bool view = !self.idle().count_changes() && !v.empty();
  py::array a = view ? py::array(py::dtype::of<Scalar>(), shape, strides, data, owner)
                     : py::array(py::dtype::of<Scalar>(), shape, strides, data);
  if (!(view && writable)) make_read_only(a);
  return a;
}

// sim.positions = array (and velocities, spins): copied in under the rules of the views.
void assign_vec3(PySimulation& self, std::vector<Vec3>& v, const py::array_t<double, py::array::c_style | py::array::forcecast>& a,
                 const char* name) {
  if (!self.idle().state_writable())
    throw std::runtime_error(std::string(name) +
                             " cannot be written in a block_hermite run: its Hermite state (forces, rates, individual "
                             "times and steps) would no longer belong to the particles; see docs/python.md");
  if (a.ndim() != 2 || a.shape(1) != 3 || static_cast<std::size_t>(a.shape(0)) != v.size())
    throw py::value_error(std::string(name) + " must have shape (" + std::to_string(v.size()) + ", 3)");
  const double* in = a.data();
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = {in[3 * i], in[3 * i + 1], in[3 * i + 2]};
}

// Steps to `target` with the GIL released; every 20 ms (and at the end) the GIL is taken back
// to let Python handle signals: Ctrl-C raises KeyboardInterrupt after a whole step.
void advance(PySimulation& self, std::int64_t target) {
  Session& s = self.idle();
  using clock = std::chrono::steady_clock;
  auto last = clock::now();
  bool interrupted = false;
  auto go_on = [&] {
    if (clock::now() - last < std::chrono::milliseconds(20)) return true;
    last = clock::now();
    py::gil_scoped_acquire gil;
    interrupted = PyErr_CheckSignals() != 0;
    return !interrupted;
  };
  self.stepping = true;
  struct Done {
    PySimulation& self;
    ~Done() { self.stepping = false; }
  } done{self};
  {
    py::gil_scoped_release release;
    s.advance_to_step(target, go_on);
  }
  if (interrupted || PyErr_CheckSignals() != 0) throw py::error_already_set();
}

std::int64_t step_of_time(const Session& s, double t) {
  if (!std::isfinite(t)) throw py::value_error("the time must be finite");
  return std::llround(t / s.world().dt);
}

py::dict energies_of(PySimulation& self) {
  Session& s = self.idle();
  const Energies e = energies(s.world(), s.model().gravity);
  py::dict d;
  d["kinetic_translational"] = e.kinetic_translational;
  d["kinetic_rotational"] = e.kinetic_rotational;
  d["potential_gravity"] = e.potential_gravity;
  const bool evaluated = s.contacts_evaluated();
  const ContactTotals c = evaluated ? s.simulation().forces().totals(s.world()) : ContactTotals{};
  d["elastic"] = evaluated ? c.elastic_energy : NAN;
  d["contacts"] = evaluated ? py::cast(c.contacts) : py::none();
  d["max_overlap_ratio"] = evaluated ? c.max_overlap_ratio : NAN;
  return d;
}

// The touching contacts of the last evaluation: pairs (i < j, by index) or walls, sorted by
// (i, j).
py::dict contacts_of(PySimulation& self, bool walls) {
  Session& s = self.idle();
  if (!s.contacts_evaluated())
    throw std::runtime_error("no contact forces since the resume: a checkpoint stores the particles' forces, not the "
                             "contacts'; step once first");
  const World& w = s.world();
  // The records list a pair from its smaller id (the contact list's orientation): turned to
  // its smaller index here, with the force on that particle (the record's negated, to the bit).
  struct Row {
    std::uint32_t i, j;
    double overlap;
    Vec3 force, rolling_spring;
  };
  std::vector<Row> rows;
  for (const ContactRecord& r : s.simulation().forces().touching_contacts(w)) {
    if (r.wall != walls) continue;
    const Vec3 f = r.normal_force + r.tangential_force;
    if (!walls && r.j < r.i) rows.push_back({r.j, r.i, r.overlap, -f, -r.history.rolling});
    else rows.push_back({r.i, r.j, r.overlap, f, r.history.rolling});
  }
  std::sort(rows.begin(), rows.end(), [](const Row& a, const Row& b) { return a.i != b.i ? a.i < b.i : a.j < b.j; });
  std::vector<std::int64_t> i, j, id_i, id_j;
  std::vector<double> overlap, force, rolling_spring;
  for (const Row& r : rows) {
    i.push_back(r.i), j.push_back(r.j), id_i.push_back(w.particles.id[r.i]);
    if (!walls) id_j.push_back(w.particles.id[r.j]);
    overlap.push_back(r.overlap);
    force.insert(force.end(), {r.force.x, r.force.y, r.force.z});
    rolling_spring.insert(rolling_spring.end(), {r.rolling_spring.x, r.rolling_spring.y, r.rolling_spring.z});
  }
  auto array = [](const auto& v) {
    using T = typename std::decay_t<decltype(v)>::value_type;
    return py::array_t<T>(static_cast<py::ssize_t>(v.size()), v.data());
  };
  py::dict d;
  d["i"] = array(i);
  d[walls ? "wall" : "j"] = array(j);
  d["id_i"] = array(id_i);
  if (!walls) d["id_j"] = array(id_j);
  d["overlap"] = array(overlap);
  const auto rows_of_3 = [&](const std::vector<double>& v) {
    return py::array_t<double>({static_cast<py::ssize_t>(overlap.size()), py::ssize_t{3}}, v.data());
  };
  d["force"] = rows_of_3(force);
  if (s.simulation().forces().resists_rolling()) d["rolling_spring"] = rows_of_3(rolling_spring);
  return d;
}

py::dict results_dict(const std::vector<std::pair<std::string, double>>& results) {
  py::dict d;
  for (const auto& [name, value] : results) d[py::str(name)] = value;
  return d;
}

py::dict analyze(PySimulation& self, const std::string& type, const py::kwargs& keys) {
  Session& s = self.idle();
  std::string text = "type = " + toml_value(py::str(type)) + "\n";
  for (auto [key, value] : keys) text += py::str(key).cast<std::string>() + " = " + toml_value(value) + "\n";
  return results_dict(analysis_results(load_analysis_text(s.scenario(), text, "analyze()"), s.world()));
}

py::dict scenario_analyses(PySimulation& self) {
  Session& s = self.idle();
  py::dict d;
  for (const AnalysisSpec& a : s.scenario().analyses)
    for (const auto& [name, value] : analysis_results(a, s.world())) d[py::str(name)] = value;
  return d;
}

}  // namespace
}  // namespace tsubu::python

PYBIND11_MODULE(_core, m) {
  using namespace tsubu;
  using python::PySimulation;
  m.doc() = "tsubu: discrete element method engine for spherical grains (docs/python.md)";
  m.attr("__version__") = kVersion;

  py::register_exception<InputError>(m, "ScenarioError", PyExc_ValueError);
  py::register_exception<NumericalError>(m, "NumericalError", PyExc_RuntimeError);
  py::register_exception<WriteError>(m, "WriteError", PyExc_OSError);
  py::register_exception<CheckpointError>(m, "CheckpointError", PyExc_RuntimeError);

  auto vec3_property = [](std::vector<Vec3>& (*array)(World&), const char* name) {
    return std::make_pair(
        [array](py::object self) {
          auto& s = self.cast<PySimulation&>();
          return python::particle_array(s, self, array(s.session.world()), s.session.state_writable());
        },
        [array, name](PySimulation& s, const py::array_t<double, py::array::c_style | py::array::forcecast>& a) {
          python::assign_vec3(s, array(s.session.world()), a, name);
        });
  };
  auto read_only = [](auto array) {
    return [array](py::object self) {
      auto& s = self.cast<PySimulation&>();
      return python::particle_array(s, self, array(s.session.world()), false);
    };
  };

  py::class_<PySimulation> sim(m, "Simulation");
  sim.def(py::init([](const py::object& scenario, const py::object& overrides) {
            return PySimulation(python::Session(python::scenario_from(scenario, overrides)));
          }),
          py::arg("scenario"), py::arg("overrides") = py::none(),
          "A fresh run of a scenario file (path) or scenario text (a str with line breaks); overrides as the "
          "command line's --set: {'key.path': value} or ['key.path=value', ...]");
  sim.def_static(
      "resume", [](const std::filesystem::path& where) { return PySimulation(python::Session::resume(where)); },
      py::arg("path"),
      "Continue from a checkpoint file, or from the newest valid checkpoint of a run's output folder (or of a folder "
      "of step_*.tsbk files)");
  sim.def("step", [](PySimulation& s, std::int64_t n) {
        if (n < 0) throw py::value_error("step(n): n must be >= 0");
        python::advance(s, s.idle().world().step + n);
      }, py::arg("n") = 1, "Take n steps of dt");
  sim.def("advance_to", [](PySimulation& s, double t) { python::advance(s, python::step_of_time(s.idle(), t)); },
          py::arg("time"), "Step until the time is t (the step round(t / dt), as the command line rounds the duration)");
  sim.def("checkpoint", [](PySimulation& s, const std::filesystem::path& file) { s.idle().checkpoint(file); },
          py::arg("path"), "Write the current state to a checkpoint file (atomically)");
  sim.def_property_readonly("time", [](PySimulation& s) { return s.idle().world().time; });
  sim.def_property_readonly("step_count", [](PySimulation& s) { return s.idle().world().step; });
  sim.def_property_readonly("dt", [](PySimulation& s) { return s.idle().world().dt; });
  sim.def_property_readonly("duration", [](PySimulation& s) { return s.idle().scenario().duration; });
  sim.def_property_readonly("name", [](PySimulation& s) { return s.idle().scenario().name; });
  sim.def_property_readonly("integrator", [](PySimulation& s) {
    switch (s.idle().scenario().integrator) {
      case Integrator::symplectic_euler: return "symplectic_euler";
      case Integrator::velocity_verlet: return "velocity_verlet";
      case Integrator::block_hermite: return "block_hermite";
    }
    return "";
  });
  sim.def_property_readonly("domain", [](PySimulation& s) {
    const Domain& d = s.idle().world().domain;
    return py::make_tuple(py::make_tuple(d.lower.x, d.lower.y, d.lower.z), py::make_tuple(d.upper.x, d.upper.y, d.upper.z));
  });
  sim.def_property_readonly("particle_count", [](PySimulation& s) { return s.idle().world().particles.size(); });
  sim.def_property_readonly("state_writable", [](PySimulation& s) { return s.idle().state_writable(); });

  const auto positions = vec3_property([](World& w) -> std::vector<Vec3>& { return w.particles.position; }, "positions");
  const auto velocities = vec3_property([](World& w) -> std::vector<Vec3>& { return w.particles.velocity; }, "velocities");
  const auto spins = vec3_property([](World& w) -> std::vector<Vec3>& { return w.particles.omega; }, "spins");
  sim.def_property("positions", positions.first, positions.second);
  sim.def_property("velocities", velocities.first, velocities.second);
  sim.def_property("spins", spins.first, spins.second);
  sim.def_property_readonly("ids", read_only([](World& w) -> auto& { return w.particles.id; }));
  sim.def_property_readonly("forces", read_only([](World& w) -> auto& { return w.particles.force; }));
  sim.def_property_readonly("torques", read_only([](World& w) -> auto& { return w.particles.torque; }));
  sim.def_property_readonly("radii", read_only([](World& w) -> auto& { return w.particles.radius; }));
  sim.def_property_readonly("masses", read_only([](World& w) -> auto& { return w.particles.mass; }));
  sim.def_property_readonly("contact_counts", read_only([](World& w) -> auto& { return w.particles.contact_count; }));

  sim.def("contacts", [](PySimulation& s) { return python::contacts_of(s, false); },
          "Touching particle pairs of the last evaluation: i, j (indices, i < j), id_i, id_j, overlap (m), force "
          "(N, on particle i; particle j gets minus it), and when a law resists rolling rolling_spring (N m, model "
          "epsd's spring torque on i, 0 under cdt)");
  sim.def("wall_contacts", [](PySimulation& s) { return python::contacts_of(s, true); },
          "Touching particle-wall contacts of the last evaluation: i, wall, id_i, overlap (m), force (N, on i), and "
          "rolling_spring (N m) when a law resists rolling");
  sim.def("energies", &python::energies_of,
          "Energies (J) and contact totals of the current state, as the columns of series.csv");
  sim.def("analyze", &python::analyze, py::arg("type"),
          "One [[analyses]] entry on the current state: analyze('solid_fraction', z_range=[a, b]) and the keys of "
          "docs/scenario.md; returns {result name: value}");
  sim.def("analyses", &python::scenario_analyses, "The scenario's own [[analyses]] on the current state");
  sim.def("__repr__", [](PySimulation& s) {
    const World& w = s.idle().world();
    return "<tsubu.Simulation '" + s.session.scenario().name + "': " + std::to_string(w.particles.size()) +
           " particles, step " + std::to_string(w.step) + ">";
  });
}
