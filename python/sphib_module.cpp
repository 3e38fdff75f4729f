// The Python module `sphib` (pybind11): scenes from files or built in Python, membranes from point
// arrays or shape functions, body forces and observers as Python callables, the library's own run
// loop and output, stepping by hand with the fields as read-only NumPy views.
//
// Scenes are validated by the scene reader itself: keys given in Python are `--set` overrides of
// the file (or of an empty scene), so a bad value is refused with the command line's message.
// Errors raise sphib.SceneError (a bad scene, ValueError), sphib.RunError (a run that failed,
// RuntimeError), ValueError (a scene the simulation refuses at set-up); a Python exception raised
// in a callback comes back as itself, with the run's message added as a note.
#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

#include "app/check.hpp"
#include "io/footprint.hpp"
#include "io/run.hpp"
#include "io/scene.hpp"
#include "membrane/geometry.hpp"
#include "membrane/hookean.hpp"
#include "membrane/shapes.hpp"
#include "sphib_version.hpp"

namespace py = pybind11;
using namespace sphib;

namespace {

// ---- Python values as TOML values (the text of a --set override) ----------------------------

std::string toml_string(const std::string& s) {
  std::string r = "\"";
  for (const char c : s) {
    switch (c) {
      case '"': r += "\\\""; break;
      case '\\': r += "\\\\"; break;
      case '\n': r += "\\n"; break;
      case '\t': r += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          r += buf;
        } else {
          r += c;
        }
    }
  }
  return r + "\"";
}

std::string toml_value(py::handle v, const std::string& key) {
  if (py::hasattr(v, "tolist") && !py::isinstance<py::str>(v)) v = v.attr("tolist")();  // NumPy scalars, arrays
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::int_>(v)) return py::str(v).cast<std::string>();
  if (py::isinstance<py::float_>(v)) {
    const double d = v.cast<double>();
    if (std::isnan(d)) return "nan";
    if (std::isinf(d)) return d > 0 ? "inf" : "-inf";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", d);
    return buf;
  }
  if (py::isinstance<py::str>(v)) return toml_string(v.cast<std::string>());
  if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
    std::string r = "[";
    for (py::handle e : v) r += (r.size() > 1 ? ", " : "") + toml_value(e, key);
    return r + "]";
  }
  throw py::type_error("scene key " + key + ": a " + py::str(v.get_type().attr("__name__")).cast<std::string>() +
                       " is not a scene value (numbers, booleans, strings and lists of them are)");
}

// {"grid": {"nx": 32}, "fluid.mu": 0.1} -> ["grid.nx=32", "fluid.mu=0.1"]
void flatten(const py::dict& d, const std::string& prefix, std::vector<std::string>& out) {
  for (auto [k, v] : d) {
    const std::string key = prefix + py::str(k).cast<std::string>();
    if (py::isinstance<py::dict>(v)) flatten(v.cast<py::dict>(), key + ".", out);
    else out.push_back(key + "=" + toml_value(v, key));
  }
}

// ---- Callbacks: Python callables behind the library's std::function hooks -------------------

// What the callbacks of one run or simulation share: the simulation whose particles they are
// asked about, and the first Python exception one of them raised.
struct Context {
  const Simulation* sim = nullptr;
  std::optional<py::error_already_set> pending;
};

// Raises a Python exception of the given type from C++ (so that `guarded` keeps it).
[[noreturn]] void raise(PyObject* type, const std::string& message) {
  PyErr_SetString(type, message.c_str());
  throw py::error_already_set();
}

// Calls fn, keeping its Python exception for re-raising after the library has unwound.
template <class F>
auto guarded(Context& ctx, F&& fn) -> decltype(fn()) {
  try {
    return fn();
  } catch (py::error_already_set& e) {
    if (!ctx.pending) ctx.pending = e;
    throw;
  }
}

// A field F(x, y[, t]) -> (Fx, Fy) written with NumPy: called once per sweep of the library over
// all particles, with arrays of their positions, and answered from that result point by point.
// A call off the sweep (another caller, other points) is evaluated alone with arrays of one.
class VectorField {
 public:
  VectorField(py::object fn, std::string what, bool with_t, Mat2 x0, std::shared_ptr<Context> ctx)
      : fn_(std::move(fn)), what_(std::move(what)), with_t_(with_t), x0_(std::move(x0)), ctx_(std::move(ctx)) {}

  Eigen::Vector2d operator()(double x, double y, double t) {
    if (valid_ && t == t_ && next_ < x_.rows() && x_(next_, 0) == x && x_(next_, 1) == y) return F_.row(next_++);
    const Mat2& now = ctx_->sim ? ctx_->sim->fluid().x() : x0_;
    if (now.rows() > 0 && now(0, 0) == x && now(0, 1) == y) {  // the start of a sweep: all at once
      x_ = now;
      F_ = evaluate(x_, t);
      t_ = t, next_ = 1, valid_ = true;
      return F_.row(0);
    }
    Mat2 one(1, 2);
    one << x, y;
    return evaluate(one, t).row(0);
  }

 private:
  Mat2 evaluate(const Mat2& x, double t) {
    return guarded(*ctx_, [&] {
      const Eigen::VectorXd xs = x.col(0), ys = x.col(1);
      py::object r = with_t_ ? fn_(xs, ys, t) : fn_(xs, ys);
      py::module_ np = py::module_::import("numpy");
      const py::ssize_t n = x.rows();
      Mat2 F(n, 2);
      py::array_t<double> a;
      if (py::isinstance<py::tuple>(r) || py::isinstance<py::list>(r)) {
        if (py::len(r) != 2) raise(PyExc_ValueError, what_ + " must return (Fx, Fy) (got " + std::to_string(py::len(r)) + " values)");
        for (int c = 0; c < 2; ++c) {
          py::array_t<double> col = np.attr("broadcast_to")(np.attr("asarray")(r[py::int_(c)], "float64"), py::make_tuple(n));
          for (py::ssize_t i = 0; i < n; ++i) F(i, c) = col.at(i);
        }
      } else {
        py::array_t<double> arr = np.attr("broadcast_to")(np.attr("asarray")(r, "float64"), py::make_tuple(n, 2));
        for (py::ssize_t i = 0; i < n; ++i) F(i, 0) = arr.at(i, 0), F(i, 1) = arr.at(i, 1);
      }
      return F;
    });
  }

  py::object fn_;
  std::string what_;
  bool with_t_;
  Mat2 x0_, x_, F_;
  std::shared_ptr<Context> ctx_;
  double t_ = 0;
  Eigen::Index next_ = 0;
  bool valid_ = false;
};

// ---- Simulations ----------------------------------------------------------------------------

// A simulation seen from Python: owned (sphib.Simulation: arrays are read-only views that keep it
// alive) or borrowed during an observer call (arrays are copies: the run's simulation ends with it).
// Membrane f and T are always those of the current markers (Simulation::update_membrane_forces).
struct PySim {
  std::shared_ptr<Context> ctx;          // the callbacks' context (owned simulations)
  std::unique_ptr<Simulation> owned;
  const Simulation* sim = nullptr;
  Scene scene;                           // what it was built from (owned simulations)

  const Simulation& get() const {
    if (!sim) throw std::logic_error("sphib.Simulation: no simulation");
    return *sim;
  }
  const MembraneState& membrane(int k) const {
    const auto& m = get().membranes();
    if (k < 0 || k >= static_cast<int>(m.size()))
      throw py::index_error("membrane " + std::to_string(k) + ": the simulation has " + std::to_string(m.size()) +
                            " membrane(s)");
    return m[k];
  }
};

// A read-only view of an array held by the simulation behind `self`, or a copy when it is borrowed.
template <class M>
py::object array(const PySim& ps, const M& m, py::handle self) {
  if (!ps.owned) return py::cast(M(m));
  return py::cast(Eigen::Ref<const M>(m), py::return_value_policy::reference_internal, self);
}

// ---- Scenes ----------------------------------------------------------------------------------

struct ExtraMembrane {
  Membrane m;
  double h_star = 0, h_star_over_h = 1.4;
  bool fixed = false;
  double viscosity_ratio = 1.0;
};

// A validated scene plus what Python adds: membranes, a body force and an initial velocity as
// callables, observers.
struct PyScene {
  std::string path;  // the scene file ("" for a scene built from keys)
  std::string name;  // for messages
  std::vector<std::string> overrides;
  Scene scene;
  std::vector<ExtraMembrane> extra;
  py::object body_force = py::none(), initial_velocity = py::none();
  std::vector<std::pair<std::string, py::object>> observers;

  void validate() { scene = path.empty() ? parse_scene("", name, overrides) : load_scene(path, overrides); }

  double h() const {
    const FluidParams& f = scene.sim.fluid;
    return f.h_over_dx * 0.5 * (f.domain.Lx() / f.nx + f.domain.Ly() / f.ny);
  }

  // The C++ scene, its callbacks bound to ctx.
  Scene build(const std::shared_ptr<Context>& ctx) const {
    Scene s = scene;
    for (const ExtraMembrane& e : extra)
      s.sim.membranes.push_back({e.m, e.h_star > 0 ? e.h_star : e.h_star_over_h * h(), e.fixed, e.viscosity_ratio});
    const Mat2 x0 = make_lattice(s.sim.fluid.domain, s.sim.fluid.nx, s.sim.fluid.ny).x;
    if (!body_force.is_none()) {
      auto f = std::make_shared<VectorField>(body_force, "body_force", true, x0, ctx);
      s.sim.body_force_field = [f](double x, double y, double t) { return (*f)(x, y, t); };
    }
    if (!initial_velocity.is_none()) {
      auto f = std::make_shared<VectorField>(initial_velocity, "initial_velocity", false, x0, ctx);
      s.sim.initial_velocity = [f](double x, double y) { return (*f)(x, y, 0.0); };
    }
    for (const auto& [oname, fn] : observers) {
      const std::string what = oname;
      py::object o = fn;
      s.observers.push_back({oname, [o, ctx, what](const Simulation& sim) {
                               return guarded(*ctx, [&] {
                                 auto view = std::make_unique<PySim>();
                                 view->sim = &sim;
                                 py::object r = o(py::cast(std::move(view)));
                                 try {
                                   return r.cast<double>();
                                 } catch (const py::cast_error&) {
                                   raise(PyExc_TypeError, "observer '" + what + "' must return a number (got " +
                                                              py::str(r.get_type().attr("__name__")).cast<std::string>() + ")");
                                 }
                               });
                             }});
    }
    return s;
  }
};

// ---- Runs ------------------------------------------------------------------------------------

std::atomic<int> g_stop{0};
extern "C" void on_signal(int sig) { g_stop.store(sig); }

// Re-raises the Python exception a callback raised (with the run's message as a note), else rethrows.
[[noreturn]] void reraise(Context& ctx, const std::exception& e) {
  if (ctx.pending) {
    py::error_already_set err = *ctx.pending;
    ctx.pending.reset();
    if (py::hasattr(err.value(), "add_note")) err.value().attr("add_note")(std::string("sphib: ") + e.what());
    throw err;
  }
  throw;
}

py::dict run(const PyScene& ps, const std::string& out, bool log, const std::string& restart) {
  auto ctx = std::make_shared<Context>();
  const Scene scene = ps.build(ctx);
  RunOptions opt;
  opt.out_dir = out;
  opt.log = log ? &std::cerr : nullptr;
  opt.restart = restart;
  opt.stop = &g_stop;
  opt.before_run = [ctx](const Simulation& sim) { ctx->sim = &sim; };  // the particles the callbacks see
  // Ctrl-C (SIGINT) and SIGTERM end the run after the current step with complete output; then
  // SIGINT raises KeyboardInterrupt and SIGTERM is delivered again to the handler it would have met.
  const bool main_thread = py::module_::import("threading").attr("current_thread")().is(
      py::module_::import("threading").attr("main_thread")());
  g_stop.store(0);
  struct Restore {
    bool on;
    void (*int_handler)(int) = SIG_DFL;
    void (*term_handler)(int) = SIG_DFL;
    void put_back() {
      if (on) std::signal(SIGINT, int_handler), std::signal(SIGTERM, term_handler);
      on = false;
    }
    ~Restore() { put_back(); }
  } restore{main_thread};
  if (main_thread) restore.int_handler = std::signal(SIGINT, on_signal), restore.term_handler = std::signal(SIGTERM, on_signal);
  nlohmann::json summary;
  try {
    summary = run_scene(scene, opt);
  } catch (const StoppedBeforeStart&) {  // nothing written; the signal follows below
  } catch (const std::exception& e) {
    ctx->sim = nullptr;
    reraise(*ctx, e);
  }
  ctx->sim = nullptr;
  restore.put_back();
  if (g_stop.load() == SIGINT) {  // the output is complete; now the interrupt
    PyErr_SetNone(PyExc_KeyboardInterrupt);
    throw py::error_already_set();
  }
  if (g_stop.load()) {
    std::raise(g_stop.load());
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
  }
  return py::module_::import("json").attr("loads")(summary.dump());
}

// n steps of an owned simulation; a failure raises RunError with the command line's message.
void step(PySim& s, long n) {
  if (!s.owned) throw py::type_error("an observer's simulation cannot be stepped");
  for (long k = 0; k < n; ++k) {
    const long n_before = s.owned->steps();
    const double t_before = s.owned->time();
    try {
      s.owned->step();
    } catch (const py::error_already_set&) {  // raised by a callback: itself
      s.ctx->pending.reset();
      throw;
    } catch (const std::exception& e) {
      std::ostringstream msg;
      msg << "step " << n_before + 1 << " (t = " << t_before + s.owned->fluid().params().dt << "): " << e.what();
      throw RunError(msg.str());
    }
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();  // Ctrl-C between steps
  }
}

// The (x, y) or point list given for a membrane.
Eigen::Vector2d pair(const std::vector<double>& v, const char* what) {
  if (v.size() != 2) throw py::value_error(std::string(what) + " must be (x, y)");
  return {v[0], v[1]};
}

}  // namespace

namespace {

// Membranes: the shape builders and the spline diagnostics.
void bind_membranes(py::module_& m) {
  py::class_<Membrane>(m, "Membrane", "A closed Hookean membrane: nb markers X labelled by rest arclength, rest length L0 = 2 pi r0, modulus T0.")
      .def_property_readonly("X", [](const Membrane& mb) -> Eigen::Ref<const Mat2> { return mb.X; },
                             py::return_value_policy::reference_internal, "marker positions (nb x 2), read-only view")
      .def_readonly("L0", &Membrane::L0)
      .def_readonly("T0", &Membrane::T0)
      .def_property_readonly("nb", &Membrane::nb)
      .def_property_readonly("ds", &Membrane::ds)
      .def("__repr__", [](const Membrane& mb) {
        std::ostringstream o;
        o << "<sphib.Membrane nb=" << mb.nb() << " L0=" << mb.L0 << " T0=" << mb.T0 << ">";
        return o.str();
      });
  m.def("circle", [](int nb, double r0, std::optional<double> radius, std::vector<double> centre, double T0) {
          const Eigen::Vector2d c = pair(centre, "centre");
          return make_membrane(circle(nb, c.x(), c.y(), radius.value_or(r0)), r0, T0);
        }, py::arg("nb"), py::arg("r0"), py::arg("radius") = py::none(), py::arg("centre") = std::vector<double>{0, 0},
        py::arg("T0") = 1.0, "A circle of the given radius (default r0: at rest) about centre.");
  m.def("ellipse", [](int nb, double r0, double rx, double ry, std::vector<double> centre, double T0) {
          const Eigen::Vector2d c = pair(centre, "centre");
          return make_membrane(ellipse(nb, c.x(), c.y(), rx, ry), r0, T0);
        }, py::arg("nb"), py::arg("r0"), py::arg("rx"), py::arg("ry"), py::arg("centre") = std::vector<double>{0, 0},
        py::arg("T0") = 1.0, "An axis-aligned ellipse with half-axes rx, ry about centre.");
  m.def("from_points", [](const Mat2& points, int nb, double r0, double T0) { return make_membrane(from_points(points, nb), r0, T0); },
        py::arg("points"), py::arg("nb"), py::arg("r0"), py::arg("T0") = 1.0,
        "A closed curve through points (m x 2, anticlockwise), resampled at nb markers uniform in arclength.");
  m.def("polar", [](const std::function<double(double)>& r, int nb, double r0, std::vector<double> centre, double T0) {
          const Eigen::Vector2d c = pair(centre, "centre");
          return make_membrane(from_polar(r, nb, c.x(), c.y()), r0, T0);
        }, py::arg("r"), py::arg("nb"), py::arg("r0"), py::arg("centre") = std::vector<double>{0, 0}, py::arg("T0") = 1.0,
        "A star-shaped curve of radius r(theta) about centre.");
  m.def("curve", [](const std::function<Eigen::Vector2d(double)>& C, int nb, double r0, double T0) {
          return make_membrane(from_curve(C, nb), r0, T0);
        }, py::arg("C"), py::arg("nb"), py::arg("r0"), py::arg("T0") = 1.0,
        "A closed curve C(t) -> (x, y), t in [0, 1), anticlockwise, C(1) = C(0).");
  m.def("measure", [](const Mat2& X, double L0, double T0) {
          MembraneDiagnostics D(static_cast<int>(X.rows()), L0);
          const MembraneShape s = D.measure(X, T0);
          py::dict d;
          d["area"] = s.area, d["cx"] = s.cx, d["cy"] = s.cy, d["rx"] = s.rx, d["ry"] = s.ry;
          d["length"] = s.length, d["elastic_energy"] = s.energy;
          return d;
        }, py::arg("X"), py::arg("L0"), py::arg("T0") = 0.0,
        "Spline diagnostics of markers X: area (exact for the spline), centroid, half-chords rx, ry, length, elastic energy.");
}

// A Simulation stepped from Python, its arrays as read-only views.
void bind_simulation(py::module_& m) {
  py::class_<PySim>(m, "Simulation",
                    "A simulation built from a Scene, stepped from Python. Arrays are read-only views of its "
                    "storage (no copies) that keep it alive; take them again after stepping. In an observer the "
                    "simulation is the run's and its arrays are copies.")
      .def(py::init([](const PyScene& ps) {
             auto s = std::make_unique<PySim>();
             s->ctx = std::make_shared<Context>();
             s->scene = ps.build(s->ctx);
             refuse_if_too_large(s->scene);  // SceneError before any allocation
             try {
               s->owned = std::make_unique<Simulation>(s->scene.sim);
             } catch (const std::exception& e) {
               reraise(*s->ctx, e);
             }
             s->sim = s->owned.get();
             s->ctx->sim = s->sim;
             return s;
           }), py::arg("scene"))
      .def("step", &step, py::arg("n") = 1,
           "Advances n time steps (without the run's blow-up guards and output: sphib.run has them).")
      .def("advance_to", [](PySim& s, double t) {
             const long n = std::lround((t - s.get().time()) / s.get().fluid().params().dt);
             if (n > 0) step(s, n);
           }, py::arg("t"), "Steps until the time is t (to the nearest step).")
      .def_property_readonly("time", [](const PySim& s) { return s.get().time(); })
      .def_property_readonly("steps", [](const PySim& s) { return s.get().steps(); })
      .def_property_readonly("dt", [](const PySim& s) { return s.get().fluid().params().dt; })
      .def_property_readonly("method", [](const PySim& s) { return s.get().fluid().params().method; })
      .def_property_readonly("particles_move", [](const PySim& s) { return s.get().fluid().particles_move(); })
      .def_property_readonly("N", [](const PySim& s) { return s.get().fluid().size(); })
      .def_property_readonly("nx", [](const PySim& s) { return s.get().fluid().lattice().nx; })
      .def_property_readonly("ny", [](const PySim& s) { return s.get().fluid().lattice().ny; })
      .def_property_readonly("dx", [](const PySim& s) { return s.get().fluid().lattice().dx; })
      .def_property_readonly("dy", [](const PySim& s) { return s.get().fluid().lattice().dy; })
      .def_property_readonly("h", [](const PySim& s) { return s.get().fluid().h(); })
      .def_property_readonly("x", [](py::object self) { const PySim& s = self.cast<const PySim&>(); return array(s, s.get().fluid().x(), self); },
                             "particle positions (N x 2; on a lattice particle i + nx j)")
      .def_property_readonly("u", [](py::object self) { const PySim& s = self.cast<const PySim&>(); return array(s, s.get().fluid().u(), self); },
                             "velocity u^n (N x 2): u[:, 0].reshape(ny, nx) is u on the lattice, still a view")
      .def_property_readonly("p", [](py::object self) { const PySim& s = self.cast<const PySim&>(); return array(s, s.get().fluid().p(), self); },
                             "pressure (N)")
      .def_property_readonly("phi", [](py::object self) { const PySim& s = self.cast<const PySim&>(); return array(s, s.get().fluid().phi(), self); },
                             "projection methods: phi^n; WCSPH: density (N)")
      .def_property_readonly("volumes", [](py::object self) { const PySim& s = self.cast<const PySim&>(); return array(s, s.get().fluid().volumes(), self); })
      .def_property_readonly("force", [](py::object self) { const PySim& s = self.cast<const PySim&>(); return array(s, s.get().force(), self); },
                             "force per unit volume of the last step on the particles, body + membranes (N x 2)")
      .def_property_readonly("membrane_count", [](const PySim& s) { return s.get().membranes().size(); })
      .def("markers", [](py::object self, int k) { const PySim& s = self.cast<const PySim&>(); return array(s, s.membrane(k).m.X, self); },
           py::arg("k") = 0, "marker positions X of membrane k (nb x 2)")
      .def("membrane_force", [](py::object self, int k) { const PySim& s = self.cast<const PySim&>(); return array(s, s.membrane(k).f, self); },
           py::arg("k") = 0, "force density f of membrane k at its markers (nb x 2)")
      .def("tension", [](py::object self, int k) { const PySim& s = self.cast<const PySim&>(); return array(s, s.membrane(k).T, self); },
           py::arg("k") = 0, "tension T of membrane k at its markers (nb)")
      .def("marker_velocity", [](py::object self, int k) { const PySim& s = self.cast<const PySim&>(); return array(s, s.membrane(k).U, self); },
           py::arg("k") = 0, "u(X) at the markers of membrane k after the last step (nb x 2)")
      .def("membrane", [](const PySim& s, int k) {
             const MembraneState& ms = s.membrane(k);
             MembraneDiagnostics D(ms.m.nb(), ms.m.L0);
             const MembraneShape sh = D.measure(ms.m.X, ms.m.T0);
             py::dict d;
             d["nb"] = ms.m.nb(), d["L0"] = ms.m.L0, d["T0"] = ms.m.T0, d["h_star"] = ms.h_star, d["fixed"] = ms.fixed;
             d["area"] = sh.area, d["cx"] = sh.cx, d["cy"] = sh.cy, d["rx"] = sh.rx, d["ry"] = sh.ry;
             d["length"] = sh.length, d["elastic_energy"] = sh.energy, d["iterations"] = ms.last.iterations;
             return d;
           }, py::arg("k") = 0, "membrane k's parameters and shape (area, centroid, rx, ry, length, elastic energy)")
      .def("kinetic_energy", [](const PySim& s) { return s.get().fluid().kinetic_energy(); })
      .def("max_div_u", [](const PySim& s) { return s.get().fluid().max_abs_divergence(); });
}

// Scenes: keys, membranes, callables and observers.
void bind_scene(py::module_& m) {
  py::class_<PyScene>(m, "Scene",
                      "What to simulate: scene keys (as in a scene file; `sphib keys` lists them), validated as "
                      "they are given, plus membranes, a body force, an initial velocity and observers from Python.")
      .def(py::init([](py::object keys, const std::string& name) {
             auto s = std::make_unique<PyScene>();
             s->name = name;
             if (!keys.is_none()) flatten(keys.cast<py::dict>(), "", s->overrides);
             s->validate();
             return s;
           }), py::arg("keys") = py::none(), py::arg("name") = "scene",
           "Scene({'domain.x': [-1, 1], 'grid': {'nx': 32, 'ny': 32}, ...}): dotted or nested keys.")
      .def("set", [](PyScene& s, py::object keys, py::kwargs kw) {
             std::vector<std::string> more;
             if (!keys.is_none()) flatten(keys.cast<py::dict>(), "", more);
             if (kw) flatten(kw, "", more);
             PyScene trial = s;
             trial.overrides.insert(trial.overrides.end(), more.begin(), more.end());
             trial.validate();  // refused: the scene stays as it was
             s = std::move(trial);
           }, py::arg("keys") = py::none(), "set({'fluid.mu': 0.05}): change scene keys (validated)")
      .def("add_membrane", [](PyScene& s, const Membrane& mb, std::optional<double> h_star, double h_star_over_h, bool fixed,
                              double viscosity_ratio) {
             if (h_star && !(*h_star > 0)) throw py::value_error("h_star must be positive");
             if (!(h_star_over_h > 0)) throw py::value_error("h_star_over_h must be positive");
             if (!(viscosity_ratio >= 0.01 && viscosity_ratio <= 100))  // the range of membrane.viscosity_ratio
               throw py::value_error("viscosity_ratio must lie in [0.01, 100] (got " + std::to_string(viscosity_ratio) + ")");
             s.extra.push_back({mb, h_star.value_or(0.0), h_star_over_h, fixed, viscosity_ratio});
           }, py::arg("membrane"), py::arg("h_star") = py::none(), py::arg("h_star_over_h") = 1.4, py::arg("fixed") = false,
           py::arg("viscosity_ratio") = 1.0,
           "Adds a membrane (sphib.circle, ellipse, polar, curve, from_points) with spreading radius h* (default 1.4 h) "
           "and the viscosity ratio mu_in / mu_out of the fluid it encloses (method eulerian).")
      .def("observe", [](PyScene& s, const std::string& name, py::function fn) {
             if (name.empty()) throw py::value_error("an observer needs a name");
             for (const auto& o : s.observers)
               if (o.first == name) throw py::value_error("observer '" + name + "' is already defined");
             s.observers.emplace_back(name, fn);
           }, py::arg("name"), py::arg("fn"),
           "fn(sim) -> float, a column of diagnostics.csv and the HDF5 series, its last value in the summary.")
      .def_property("body_force", [](const PyScene& s) { return s.body_force; },
                    [](PyScene& s, py::object f) {
                      if (!f.is_none() && !PyCallable_Check(f.ptr())) throw py::type_error("body_force must be callable F(x, y, t)");
                      s.body_force = f;
                    },
                    "F(x, y, t) -> (Fx, Fy) per unit volume, called with NumPy arrays of all particle positions once per step")
      .def_property("initial_velocity", [](const PyScene& s) { return s.initial_velocity; },
                    [](PyScene& s, py::object f) {
                      if (!f.is_none() && !PyCallable_Check(f.ptr())) throw py::type_error("initial_velocity must be callable u0(x, y)");
                      s.initial_velocity = f;
                    },
                    "u0(x, y) -> (u, v), called with NumPy arrays of the particle positions")
      .def("check", [](const PyScene& s) {
             auto ctx = std::make_shared<Context>();
             std::ostringstream o;
             try {
               sphib::app::check_scene(s.build(ctx), o);
             } catch (const std::exception& e) {
               reraise(*ctx, e);
             }
             return o.str();
           }, "What `sphib check` prints: particles, neighbours, memory, time-step estimates and warnings.")
      .def_property_readonly("path", [](const PyScene& s) { return s.path; })
      .def_property_readonly("title", [](const PyScene& s) { return s.scene.title; })
      .def_property_readonly("method", [](const PyScene& s) { return s.scene.method; })
      .def_property_readonly("nx", [](const PyScene& s) { return s.scene.sim.fluid.nx; })
      .def_property_readonly("ny", [](const PyScene& s) { return s.scene.sim.fluid.ny; })
      .def_property_readonly("dx", [](const PyScene& s) { return s.scene.sim.fluid.domain.Lx() / s.scene.sim.fluid.nx; })
      .def_property_readonly("dy", [](const PyScene& s) { return s.scene.sim.fluid.domain.Ly() / s.scene.sim.fluid.ny; })
      .def_property_readonly("h", &PyScene::h)
      .def_property_readonly("dt", [](const PyScene& s) { return s.scene.sim.fluid.dt; })
      .def_property_readonly("end", [](const PyScene& s) { return s.scene.t_end; })
      .def_property_readonly("rho", [](const PyScene& s) { return s.scene.sim.fluid.rho; })
      .def_property_readonly("mu", [](const PyScene& s) { return s.scene.sim.fluid.mu; })
      .def_property_readonly("domain", [](const PyScene& s) {
        const Domain& d = s.scene.sim.fluid.domain;
        return py::make_tuple(py::make_tuple(d.x0, d.x1), py::make_tuple(d.y0, d.y1));
      })
      .def_property_readonly("membrane_count", [](const PyScene& s) { return s.scene.sim.membranes.size() + s.extra.size(); })
      .def_property_readonly("keys", [](const PyScene& s) {
        py::dict d;
        for (const auto& [k, v] : s.scene.resolved) d[py::str(k)] = v;
        return d;
      }, "every key given, as the run records it (text)")
      .def("__repr__", [](const PyScene& s) {
        std::ostringstream o;
        o << "<sphib.Scene " << (s.path.empty() ? s.name : s.path) << ": " << s.scene.method << ", " << s.scene.sim.fluid.nx
          << " x " << s.scene.sim.fluid.ny << ", dt " << s.scene.sim.fluid.dt << ", end " << s.scene.t_end << ", "
          << s.scene.sim.membranes.size() + s.extra.size() << " membrane(s)>";
        return o.str();
      });
}

// Loading and running scenes.
void bind_running(py::module_& m) {
  m.def("load_scene", [](const std::string& path, py::object set) {
          auto s = std::make_unique<PyScene>();
          s->path = s->name = path;
          if (!set.is_none()) flatten(set.cast<py::dict>(), "", s->overrides);
          s->validate();
          return s;
        }, py::arg("path"), py::arg("set") = py::none(),
        "Reads a scene file with overrides: load_scene('cases/membrane_oscillation.toml', set={'grid.nx': 32}).");
  m.def("run", &run, py::arg("scene"), py::arg("out") = "out", py::arg("log") = false, py::arg("restart") = "",
        "Runs the scene with the library's loop into out (output.h5, .xdmf, diagnostics.csv, summary.json, "
        "checkpoint.h5); returns the summary as a dict. restart: a checkpoint to continue from. Ctrl-C ends the "
        "run after the current step with complete output, then raises KeyboardInterrupt.");
  m.def("scene_keys", [] { return describe_scene_keys(); }, "The table `sphib keys` prints (Markdown rows).");
}

}  // namespace

PYBIND11_MODULE(sphib, m) {
  m.doc() = "sphib: immersed-boundary fluid-structure interaction with projection SPH (Python bindings)";
  m.attr("__version__") = SPHIB_VERSION;
  py::register_exception<SceneError>(m, "SceneError", PyExc_ValueError);
  py::register_exception<RunError>(m, "RunError", PyExc_RuntimeError);
  bind_membranes(m);
  bind_simulation(m);
  bind_scene(m);
  bind_running(m);
}
