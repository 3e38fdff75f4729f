// The Python module `sphib` (pybind11): scenes from files or built in Python, membranes from point
// arrays or shape functions, body forces and observers as Python callables, the library's own run
// loop and output, stepping by hand with the fields as read-only NumPy views, and the membrane
// analyses of membrane/polygon.hpp (ellipse fit, Taylor deformation, inclination, angular velocity).
//
// One validation path: keys given in Python are `--set` overrides of the file (or of an empty scene),
// each Python value written as the TOML literal of its type (an int stays an integer, a float a
// number), and membranes built in Python are handed to the scene reader with the file's
// (io/scene.hpp build_scene), so a bad value or membrane is refused with the command line's message.
// Errors raise sphib.SceneError (a bad scene, ValueError), sphib.RunError (a run that failed,
// RuntimeError), ValueError (a scene the simulation refuses at set-up); a Python exception raised
// in a callback comes back as itself, with the run's message added as a note.
#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <atomic>
#include <cmath>
#include <climits>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

#include "io/check.hpp"
#include "io/footprint.hpp"
#include "io/run.hpp"
#include "io/scene.hpp"
#include "io/scene_checks.hpp"
#include "membrane/geometry.hpp"
#include "membrane/force.hpp"
#include "membrane/polygon.hpp"
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

std::string py_type_name(py::handle v) { return py::str(py::type::of(v).attr("__name__")).cast<std::string>(); }

// A Python value as the TOML literal of its type, so that the scene reader applies a file's rules:
// bool (and numpy.bool_) -> true/false; an integer (int, numpy integers: numbers.Integral) -> an
// integer; a real (float, numpy.float32/64: numbers.Real) -> a number, always written with a point
// or an exponent (40.0 stays a number, which grid.nx refuses as a file does); str and os.PathLike
// -> a string; list, tuple and NumPy arrays -> arrays; a 0-d array or NumPy scalar -> its item.
std::string toml_value(py::handle v, const std::string& key, int depth = 0) {
  if (depth > 8)  // no scene value nests deeper; a list that contains itself would never end
    throw py::value_error("scene key " + key + ": lists nested more than 8 deep are not a scene value");
  py::module_ np = py::module_::import("numpy"), numbers = py::module_::import("numbers");
  if (py::isinstance(v, np.attr("ndarray"))) {
    py::object plain = v.attr("ndim").cast<int>() == 0 ? v.attr("item")() : v.attr("tolist")();  // held while read
    return toml_value(plain, key, depth);
  }
  if (py::isinstance(v, np.attr("generic"))) {
    py::object item = v.attr("item")();
    return toml_value(item, key, depth);
  }
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>() ? "true" : "false";
  if (py::isinstance(v, numbers.attr("Integral"))) {
    py::object i = py::module_::import("operator").attr("index")(v);
    int overflow = 0;
    const long long n = PyLong_AsLongLongAndOverflow(i.ptr(), &overflow);
    if (overflow)
      throw SceneError("(--set " + key + "): value " + py::str(i).cast<std::string>() +
                       " is out of range (a scene's integers are 64-bit)");
    return std::to_string(n);
  }
  if (py::isinstance(v, numbers.attr("Real"))) {
    const double d = py::float_(py::reinterpret_borrow<py::object>(v)).cast<double>();
    if (std::isnan(d)) return "nan";
    if (std::isinf(d)) return d > 0 ? "inf" : "-inf";
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", d);
    std::string t = buf;
    if (t.find_first_of(".e") == std::string::npos) t += ".0";
    return t;
  }
  if (py::isinstance<py::str>(v)) return toml_string(v.cast<std::string>());
  if (py::hasattr(v, "__fspath__")) {
    py::object path = py::module_::import("os").attr("fspath")(v);
    if (!py::isinstance<py::str>(path)) throw py::type_error("scene key " + key + ": a bytes path is not a scene value (give str)");
    return toml_value(path, key, depth);
  }
  if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
    std::string r = "[";
    for (py::handle e : v) r += (r.size() > 1 ? ", " : "") + toml_value(e, key, depth + 1);
    return r + "]";
  }
  throw py::type_error("scene key " + key + ": a " + py_type_name(v) +
                       " is not a scene value (numbers, booleans, strings, paths and lists or arrays of them are)");
}

// {"grid": {"nx": 32}, "fluid.mu": 0.1} -> ["grid.nx=32", "fluid.mu=0.1"]
void flatten(const py::dict& d, const std::string& prefix, std::vector<std::string>& out, int depth = 0) {
  if (depth > 8) throw py::value_error("scene key " + prefix + "..: tables nested more than 8 deep are not a scene");
  for (auto [k, v] : d) {
    if (!py::isinstance<py::str>(k)) throw py::type_error("scene keys are strings (got a " + py_type_name(k) + ")");
    const std::string key = prefix + k.cast<std::string>();
    if (py::isinstance<py::dict>(v)) flatten(v.cast<py::dict>(), key + ".", out, depth + 1);
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
// alive) or lent to an observer for one call (arrays are copies; after the call it refuses every
// access: the run's simulation ends with the run, so nothing may reach it later).
// Membrane f and T are always those of the current markers (Simulation::update_membrane_forces).
struct PySim {
  std::shared_ptr<Context> ctx;          // the callbacks' context (owned simulations)
  std::unique_ptr<Simulation> owned;
  const Simulation* sim = nullptr;
  Scene scene;                           // what it was built from (owned simulations)
  std::string lent_to;                   // the observer it was lent to ("" when owned)

  const Simulation& get() const {
    if (!sim)
      throw std::runtime_error("this sphib.Simulation was lent to observer '" + lent_to +
                               "' for one call, which has returned: keep numbers or copies of arrays, not the simulation");
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

// A read-only view of an array held by the simulation behind `ps` (the view keeps it alive), or a
// copy when it is lent.
template <class M>
py::array view_of(const PySim& ps, const M& m) {
  if (!ps.owned) return py::cast(M(m));
  py::object self = py::cast(&ps, py::return_value_policy::reference);  // the existing Python object
  return py::cast(Eigen::Ref<const M>(m), py::return_value_policy::reference_internal, self);
}

// ---- Scenes ----------------------------------------------------------------------------------

// A validated scene plus what Python adds: a body force and an initial velocity as callables,
// observers. Its membranes built in Python are part of the validated scene (io/scene.hpp build_scene).
struct PyScene {
  std::string path;  // the scene file ("" for a scene built from keys)
  std::string name;  // for messages
  std::vector<std::string> overrides;
  std::vector<ProgramMembrane> added;
  Scene scene;
  py::object body_force = py::none(), initial_velocity = py::none();
  std::vector<std::pair<std::string, py::object>> observers;

  // While it is being built: membranes may still be added (rules that need them wait for assemble).
  void validate() { scene = build_scene(path, name, overrides, added, true); }

  double h() const {
    const FluidParams& f = scene.sim.fluid;
    return f.h_over_dx * 0.5 * (f.domain.Lx() / f.nx + f.domain.Ly() / f.ny);
  }

  // The C++ scene, its callbacks bound to ctx.
  Scene assemble(const std::shared_ptr<Context>& ctx) const {
    Scene s = build_scene(path, name, overrides, added);  // every rule, the membranes now complete
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
                                 // Lent for this call only: the view forgets the simulation when it returns.
                                 auto lent = std::make_unique<PySim>();
                                 lent->sim = &sim;
                                 lent->lent_to = what;
                                 PySim* view = lent.get();
                                 py::object pyview = py::cast(std::move(lent));
                                 struct Expire {
                                   PySim* v;
                                   ~Expire() { v->sim = nullptr; }
                                 } expire{view};
                                 py::object r = o(pyview);
                                 try {
                                   return r.cast<double>();
                                 } catch (const py::cast_error&) {
                                   raise(PyExc_TypeError, "observer '" + what + "' must return a number (got " + py_type_name(r) + ")");
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

py::dict run(const PyScene& ps, const std::filesystem::path& out, bool log, const std::optional<std::filesystem::path>& restart) {
  auto ctx = std::make_shared<Context>();
  const Scene scene = ps.assemble(ctx);
  RunOptions opt;
  opt.out_dir = out.string();
  opt.log = log ? &std::cerr : nullptr;
  opt.restart = restart ? restart->string() : "";
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

// The run's loop has no place to stop between calls; a step count or a time it cannot reach is an error.
long checked_steps(long n) {
  if (n < 0) throw py::value_error("step: n must be >= 0 (got " + std::to_string(n) + ")");
  return n;
}

// n steps of an owned simulation; a failure raises RunError with the command line's message.
void step(PySim& s, long n) {
  if (!s.owned) throw py::type_error("an observer's simulation cannot be stepped");
  for (long k = 0, steps = checked_steps(n); k < steps; ++k) {
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
Eigen::Vector2d point2(const std::vector<double>& v, const char* what) {
  if (v.size() != 2) throw py::value_error(std::string(what) + " must be (x, y)");
  return {v[0], v[1]};
}

// A shape builder's marker count, refused before the markers are made by the scene reader's rule.
int marker_count(long nb) {
  if (nb < 4 || nb > kMaxMarkers)
    throw SceneError("nb: value " + std::to_string(nb) + " is out of range (allowed: [4, " + std::to_string(kMaxMarkers) + "])");
  return static_cast<int>(nb);
}

// Marker positions given to an analysis: at least three finite points.
const Mat2& markers_arg(const Mat2& X, const char* what = "X") {
  if (X.rows() < 3) throw py::value_error(std::string(what) + " must hold at least 3 markers (nb x 2)");
  if (!X.allFinite()) throw py::value_error(std::string(what) + " holds non-finite values");
  return X;
}

py::dict shape_dict(const MembraneShape& s) {
  py::dict d;
  d["area"] = s.area, d["cx"] = s.cx, d["cy"] = s.cy, d["rx"] = s.rx, d["ry"] = s.ry;
  d["length"] = s.length, d["elastic_energy"] = s.energy;
  d["D"] = s.moments.deformation(), d["inclination"] = s.moments.theta;  // the spline's second moments
  return d;
}

// Membranes: the shape builders, the spline diagnostics and the ellipse fit.
void bind_membranes(py::module_& m) {
  py::class_<Membrane>(m, "Membrane",
                       "A closed membrane: nb markers X labelled by the reference's arclength (length L0), its law "
                       "(hookean, neo_hookean, skalak, inextensible), modulus Es (the Hookean T0) and bending modulus Eb.")
      .def_property_readonly("X", [](const Membrane& mb) -> Eigen::Ref<const Mat2> { return mb.X; },
                             py::return_value_policy::reference_internal, "marker positions (nb x 2), read-only view")
      .def_property_readonly("L0", &Membrane::L0, "length of the reference (the label s runs over [0, L0))")
      .def_property_readonly("T0", [](const Membrane& mb) { return mb.mat.Es; }, "the Hookean modulus T0 of Eq. (47) (= Es)")
      .def_property_readonly("Es", [](const Membrane& mb) { return mb.mat.Es; }, "the law's modulus")
      .def_property_readonly("Eb", [](const Membrane& mb) { return mb.mat.Eb; }, "bending modulus")
      .def_property_readonly("law", [](const Membrane& mb) { return mb.mat.law; }, "tension law")
      .def_property_readonly("nb", &Membrane::nb, "number of markers")
      .def_property_readonly("ds", &Membrane::ds, "label spacing L0 / nb")
      .def("__repr__", [](const Membrane& mb) {
        std::ostringstream o;
        o << "<sphib.Membrane nb=" << mb.nb() << " L0=" << mb.L0() << " " << describe(mb.mat) << ">";
        return o.str();
      });
  // The material keywords of every builder (the scene's membrane.law, T0/Es, C, Eb, kappa0, reference, prestretch).
  struct Mat {
    std::string law, reference;
    std::optional<double> T0, Es, C, kappa0;
    double Eb;
    std::optional<double> prestretch;
    // The rest radius as the scene reader takes membrane.r0: needed by reference = "circle", refused by
    // "initial" (whose reference is the initial shape); prestretch only with "initial".
    static double rest_radius(const std::string& reference, std::optional<double> r0, std::optional<double> prestretch) {
      if (reference == "circle") {
        if (!r0) throw py::value_error("r0: the rest radius is needed with reference = \"circle\" (the default)");
        if (prestretch) throw py::value_error("prestretch applies to reference = \"initial\" only");
        return *r0;
      }
      if (r0) throw py::value_error("r0 is the radius of reference = \"circle\"; with reference = \"initial\" the initial shape is the reference");
      return 0.0;
    }
    Membrane membrane(Mat2 X, std::optional<double> r0) const {
      if (reference != "circle" && reference != "initial")
        throw py::value_error("reference must be \"circle\" or \"initial\" (got \"" + reference + "\")");
      const double rest = rest_radius(reference, r0, prestretch);
      Material mat;
      mat.law = law;
      if (T0 && Es) throw py::value_error("give T0 or Es, not both (T0 is the Hookean law's Es)");
      if (T0 && law != "hookean") throw py::value_error("T0 is the Hookean law's modulus; law \"" + law + "\" takes Es");
      mat.Es = T0 ? *T0 : Es ? *Es : 1.0;
      if (C) {
        if (law != "skalak") throw py::value_error("C applies to law \"skalak\" only");
        mat.params = {*C};
      }
      mat.Eb = Eb;
      if (kappa0) mat.spontaneous = true, mat.spontaneous_curvature = *kappa0;
      Reference ref = reference == "circle" ? circle_reference(rest) : initial_reference(X, prestretch.value_or(1.0));
      // Not checked here: Scene.add_membrane checks it as the scene reader checks a file's, naming the key.
      return Membrane{std::move(X), std::move(ref), std::move(mat)};
    }
  };
#define SPHIB_MAT_ARGS                                                                                             \
  py::kw_only(), py::arg("T0") = py::none(), py::arg("law") = "hookean", py::arg("Es") = py::none(),              \
      py::arg("Eb") = 0.0, py::arg("C") = py::none(), py::arg("kappa0") = py::none(),                              \
      py::arg("reference") = "circle", py::arg("prestretch") = py::none()
#define SPHIB_MAT_PARAMS                                                                                           \
  std::optional<double> T0, const std::string &law, std::optional<double> Es, double Eb, std::optional<double> C, \
      std::optional<double> kappa0, const std::string &reference, std::optional<double> prestretch
#define SPHIB_MAT Mat{law, reference, T0, Es, C, kappa0, Eb, prestretch}
  // r0: the rest radius of reference = "circle" (needed there, refused with "initial", as membrane.r0).
  using R0 = std::optional<double>;
  m.def("circle", [](long nb, R0 r0, std::optional<double> radius, std::vector<double> centre, SPHIB_MAT_PARAMS) {
          const Eigen::Vector2d c = point2(centre, "centre");
          if (!radius && !r0) throw py::value_error("radius: a circle needs its radius (or r0, the rest radius it defaults to)");
          return SPHIB_MAT.membrane(circle(marker_count(nb), c.x(), c.y(), radius ? *radius : *r0), r0);
        }, py::arg("nb"), py::arg("r0") = py::none(), py::arg("radius") = py::none(), py::arg("centre") = std::vector<double>{0, 0},
        SPHIB_MAT_ARGS, "A circle of the given radius (default r0: at rest) about centre.");
  m.def("ellipse", [](long nb, R0 r0, double rx, double ry, std::vector<double> centre, const std::string& spacing,
                      SPHIB_MAT_PARAMS) {
          const Eigen::Vector2d c = point2(centre, "centre");
          if (spacing != "angle" && spacing != "arclength")
            throw py::value_error("spacing must be \"angle\" or \"arclength\" (got \"" + spacing + "\")");
          const int n = marker_count(nb);
          return SPHIB_MAT.membrane(spacing == "arclength" ? ellipse_by_arclength(n, c.x(), c.y(), rx, ry)
                                                           : ellipse(n, c.x(), c.y(), rx, ry), r0);
        }, py::arg("nb"), py::arg("r0") = py::none(), py::arg("rx"), py::arg("ry"), py::arg("centre") = std::vector<double>{0, 0},
        py::arg("spacing") = "angle", SPHIB_MAT_ARGS,
        "An axis-aligned ellipse with half-axes rx, ry about centre, its markers uniform in the angle (spacing = "
        "\"angle\", the paper's) or in its arclength (\"arclength\"), as membrane.spacing.");
  m.def("from_points", [](const Mat2& points, long nb, R0 r0, SPHIB_MAT_PARAMS) {
          return SPHIB_MAT.membrane(from_points(points, marker_count(nb)), r0);
        },
        py::arg("points"), py::arg("nb"), py::arg("r0") = py::none(), SPHIB_MAT_ARGS,
        "A closed curve through points (m x 2, anticlockwise), resampled at nb markers uniform in arclength.");
  m.def("polar", [](const std::function<double(double)>& r, long nb, R0 r0, std::vector<double> centre, SPHIB_MAT_PARAMS) {
          const Eigen::Vector2d c = point2(centre, "centre");
          return SPHIB_MAT.membrane(from_polar(r, marker_count(nb), c.x(), c.y()), r0);
        }, py::arg("r"), py::arg("nb"), py::arg("r0") = py::none(), py::arg("centre") = std::vector<double>{0, 0}, SPHIB_MAT_ARGS,
        "A star-shaped curve of radius r(theta) about centre.");
  m.def("curve", [](const std::function<Eigen::Vector2d(double)>& C_, long nb, R0 r0, SPHIB_MAT_PARAMS) {
          return SPHIB_MAT.membrane(from_curve(C_, marker_count(nb)), r0);
        }, py::arg("C"), py::arg("nb"), py::arg("r0") = py::none(), SPHIB_MAT_ARGS,
        "A closed curve C(t) -> (x, y), t in [0, 1), anticlockwise, C(1) = C(0).");
#undef SPHIB_MAT_ARGS
#undef SPHIB_MAT_PARAMS
#undef SPHIB_MAT
  m.def("measure", [](const Mat2& X, double L0, double T0) {
          MembraneDiagnostics D(static_cast<int>(markers_arg(X).rows()), L0);
          py::dict d = shape_dict(D.measure(X));
          MembraneForce E(make_membrane(X, L0 / (2.0 * 3.14159265358979323846), T0));
          E.fit_energy(X);
          d["elastic_energy"] = E.energy().total();
          return d;
        }, py::arg("X"), py::arg("L0"), py::arg("T0") = 0.0,
        "Spline diagnostics of markers X: area (exact for the spline), centroid, half-chords rx, ry (the extents "
        "along x and y: for a tilted shape use ellipse_fit), length, the Hookean elastic energy with modulus T0 on the "
        "circle of length L0, and D and inclination of the ellipse of the spline's second moments.");

  py::class_<ShapeMoments>(m, "ShapeMoments",
                           "Area moments of the polygon through the markers and the ellipse with the same moments "
                           "(membrane/polygon.hpp): for an ellipse its own half-axes L >= B and inclination theta.")
      .def_readonly("area", &ShapeMoments::area, "enclosed area of the polygon")
      .def_property_readonly("centroid", [](const ShapeMoments& e) { return std::make_tuple(e.centroid.x(), e.centroid.y()); },
                             "(cx, cy)")
      .def_readonly("Jxx", &ShapeMoments::Jxx, "central second moment int (x - cx)^2 dA")
      .def_readonly("Jxy", &ShapeMoments::Jxy, "central second moment int (x - cx)(y - cy) dA")
      .def_readonly("Jyy", &ShapeMoments::Jyy, "central second moment int (y - cy)^2 dA")
      .def_readonly("L", &ShapeMoments::L, "the equivalent ellipse's major half-axis")
      .def_readonly("B", &ShapeMoments::B, "the equivalent ellipse's minor half-axis")
      .def_readonly("theta", &ShapeMoments::theta, "inclination of the major axis to the x axis, radians in (-pi/2, pi/2]")
      .def_property_readonly("deformation", &ShapeMoments::deformation, "Taylor deformation D = (L - B)/(L + B)")
      .def("__repr__", [](const ShapeMoments& e) {
        std::ostringstream o;
        o << "<sphib.ShapeMoments L=" << e.L << " B=" << e.B << " D=" << e.deformation() << " theta=" << e.theta << ">";
        return o.str();
      });
  m.def("ellipse_fit", [](const Mat2& X) { return ellipse_fit(markers_arg(X)); }, py::arg("X"),
        "The ellipse with the area moments of the polygon through markers X (nb x 2): L, B, theta, deformation.");
  m.def("taylor_deformation", [](const Mat2& X) { return ellipse_fit(markers_arg(X)).deformation(); }, py::arg("X"),
        "Taylor deformation D = (L - B)/(L + B) of the ellipse fitted to markers X by their second moments "
        "(right for a tilted shape, unlike half-chords).");
  m.def("inclination", [](const Mat2& X) { return ellipse_fit(markers_arg(X)).theta; }, py::arg("X"),
        "Inclination of the fitted ellipse's major axis to the x axis, radians in (-pi/2, pi/2].");
  m.def("angular_velocity", [](const Mat2& X, const Mat2& U, std::optional<std::vector<double>> centre) {
          markers_arg(X);
          if (U.rows() != X.rows()) throw py::value_error("U must have the shape of X (nb x 2)");
          const Eigen::Vector2d c = centre ? point2(*centre, "centre") : ellipse_fit(X).centroid;
          return mean_angular_velocity(X, markers_arg(U, "U"), c);
        }, py::arg("X"), py::arg("U"), py::arg("centre") = py::none(),
        "Mean angular velocity of markers X moving at U about centre (default: the polygon's centroid): "
        "the mean over markers of (X - c) x U / norm(X - c)^2, > 0 anticlockwise; a tank-treading membrane's frequency.");
}

// Scenes: keys, membranes, callables and observers.
void bind_scene(py::module_& m) {
  py::class_<PyScene>(m, "Scene",
                      "What to simulate: scene keys (as in a scene file; `sphib keys` lists them), validated as "
                      "they are given by the scene reader, plus membranes, a body force, an initial velocity and "
                      "observers from Python.")
      .def(py::init([](std::optional<py::dict> keys, const std::string& name) {
             auto s = std::make_unique<PyScene>();
             s->name = name;
             if (keys) flatten(*keys, "", s->overrides);
             s->validate();
             return s;
           }), py::arg("keys") = py::none(), py::arg("name") = "scene",
           "Scene({'domain.x': [-1, 1], 'grid': {'nx': 32, 'ny': 32}, ...}): dotted or nested keys.")
      .def("set", [](PyScene& s, std::optional<py::dict> keys, py::kwargs kw) {
             std::vector<std::string> more;
             if (keys) flatten(*keys, "", more);
             if (kw) flatten(kw, "", more);
             PyScene trial = s;
             trial.overrides.insert(trial.overrides.end(), more.begin(), more.end());
             trial.validate();  // refused: the scene stays as it was
             s = std::move(trial);
           }, py::arg("keys") = py::none(), "set({'fluid.mu': 0.05}): change scene keys (validated)")
      .def("add_membrane", [](PyScene& s, const Membrane& mb, std::optional<double> h_star, double h_star_over_h, bool fixed,
                              double viscosity_ratio, std::optional<bool> semi_implicit, bool stiff_residual,
                              std::optional<double> tension_cutoff) {
             PyScene trial = s;
             trial.added.push_back({mb, h_star.value_or(0.0), h_star_over_h, fixed, viscosity_ratio, semi_implicit, stiff_residual,
                                    tension_cutoff});
             trial.validate();  // checked with the scene's own membranes; refused: the scene stays as it was
             s = std::move(trial);
           }, py::arg("membrane"), py::arg("h_star") = py::none(), py::arg("h_star_over_h") = 1.4, py::arg("fixed") = false,
           py::arg("viscosity_ratio") = 1.0, py::arg("semi_implicit") = py::none(), py::arg("stiff_residual") = false,
           py::arg("tension_cutoff") = py::none(),
           "Adds a membrane (sphib.circle, ellipse, polar, curve, from_points) with spreading radius h* (default "
           "1.4 h) and the viscosity ratio mu_in / mu_out of the fluid it encloses (method eulerian), checked as a "
           "scene file's membranes are (values, crossings, observe.exact). semi_implicit and stiff_residual are the "
           "scene's membrane.semi_implicit (default: with bending or a law other than hookean) and membrane.stiff_residual; "
           "tension_cutoff is membrane.tension_cutoff (default: 2 dx for law inextensible, 0 for the others).")
      .def("observe", [](PyScene& s, const std::string& name, py::function fn) {
             if (name.empty()) throw py::value_error("an observer needs a name");
             for (const auto& o : s.observers)
               if (o.first == name) throw py::value_error("observer '" + name + "' is already defined");
             s.observers.emplace_back(name, fn);
           }, py::arg("name"), py::arg("fn"),
           "fn(sim) -> float, a column of diagnostics.csv and the HDF5 series, its last value in the summary. "
           "The simulation fn receives is lent for that call only.")
      .def_property("body_force", [](const PyScene& s) -> std::optional<py::function> {
                      if (s.body_force.is_none()) return std::nullopt;
                      return py::reinterpret_borrow<py::function>(s.body_force);
                    },
                    [](PyScene& s, std::optional<py::function> f) { s.body_force = f ? py::object(*f) : py::none(); },
                    "F(x, y, t) -> (Fx, Fy) per unit volume, called with NumPy arrays of all particle positions once per step")
      .def_property("initial_velocity", [](const PyScene& s) -> std::optional<py::function> {
                      if (s.initial_velocity.is_none()) return std::nullopt;
                      return py::reinterpret_borrow<py::function>(s.initial_velocity);
                    },
                    [](PyScene& s, std::optional<py::function> f) { s.initial_velocity = f ? py::object(*f) : py::none(); },
                    "u0(x, y) -> (u, v), called with NumPy arrays of the particle positions")
      .def("check", [](const PyScene& s) {
             auto ctx = std::make_shared<Context>();
             std::ostringstream o;
             try {
               sphib::check_scene(s.assemble(ctx), o);
             } catch (const std::exception& e) {
               reraise(*ctx, e);
             }
             return o.str();
           }, "What `sphib check` prints: particles, neighbours, memory, time-step estimates and warnings.")
      .def_property_readonly("path", [](const PyScene& s) { return s.path; }, "the scene file ('' when built from keys)")
      .def_property_readonly("title", [](const PyScene& s) { return s.scene.title; }, "the scene's title key")
      .def_property_readonly("method", [](const PyScene& s) { return std::string(to_string(s.scene.method)); }, "eulerian, lagrangian, wcsph or isph")
      .def_property_readonly("nx", [](const PyScene& s) { return s.scene.sim.fluid.nx; }, "grid.nx")
      .def_property_readonly("ny", [](const PyScene& s) { return s.scene.sim.fluid.ny; }, "grid.ny")
      .def_property_readonly("dx", [](const PyScene& s) { return s.scene.sim.fluid.domain.Lx() / s.scene.sim.fluid.nx; }, "lattice spacing along x")
      .def_property_readonly("dy", [](const PyScene& s) { return s.scene.sim.fluid.domain.Ly() / s.scene.sim.fluid.ny; }, "lattice spacing along y")
      .def_property_readonly("h", &PyScene::h, "smoothing length h = kernel.h_over_dx (dx + dy)/2")
      .def_property_readonly("dt", [](const PyScene& s) { return s.scene.sim.fluid.dt; }, "time.dt")
      .def_property_readonly("end", [](const PyScene& s) { return s.scene.t_end; }, "time.end")
      .def_property_readonly("rho", [](const PyScene& s) { return s.scene.sim.fluid.rho; }, "fluid.rho")
      .def_property_readonly("mu", [](const PyScene& s) { return s.scene.sim.fluid.mu; }, "fluid.mu")
      .def_property_readonly("domain", [](const PyScene& s) {
        const Domain& d = s.scene.sim.fluid.domain;
        return std::make_tuple(std::make_tuple(d.x0, d.x1), std::make_tuple(d.y0, d.y1));
      }, "((x0, x1), (y0, y1))")
      .def_property_readonly("membrane_count", [](const PyScene& s) { return s.scene.sim.membranes.size(); },
                             "membranes of the scene file and those added")
      .def_property_readonly("keys", [](const PyScene& s) {
        std::map<std::string, std::string> d;
        for (const auto& [k, v] : s.scene.resolved) d[k] = v;
        return d;
      }, "every key, given or default, as the run records it (text)")
      .def("__repr__", [](const PyScene& s) {
        std::ostringstream o;
        o << "<sphib.Scene " << (s.path.empty() ? s.name : s.path) << ": " << to_string(s.scene.method) << ", " << s.scene.sim.fluid.nx
          << " x " << s.scene.sim.fluid.ny << ", dt " << s.scene.sim.fluid.dt << ", end " << s.scene.t_end << ", "
          << s.scene.sim.membranes.size() << " membrane(s)>";
        return o.str();
      });
}

// A Simulation stepped from Python, its arrays as read-only views.
void bind_simulation(py::module_& m) {
  py::class_<PySim>(m, "Simulation",
                    "A simulation built from a Scene, stepped from Python. Arrays are read-only views of its "
                    "storage (no copies) that keep it alive; take them again after stepping. An observer receives "
                    "the run's simulation for one call: its arrays are copies, and it refuses access after the call.")
      .def(py::init([](const PyScene& ps) {
             auto s = std::make_unique<PySim>();
             s->ctx = std::make_shared<Context>();
             s->scene = ps.assemble(s->ctx);
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
           "Advances n >= 0 time steps (without the run's blow-up guards and output: sphib.run has them).")
      .def("advance_to", [](PySim& s, double t) {
             const double now = s.get().time(), dt = s.get().fluid().params().dt;
             if (!std::isfinite(t)) throw py::value_error("advance_to: t must be finite (got " + number_text(t) + ")");
             if (t < now - 0.5 * dt)
               throw py::value_error("advance_to: t = " + number_text(t) + " is before the simulation's time " +
                                     number_text(now) + " (a simulation only steps forward)");
             const double n = std::round((t - now) / dt);
             if (n > static_cast<double>(kMaxSteps))
               throw py::value_error("advance_to: t = " + number_text(t) + " is more than " +
                                     number_text(static_cast<double>(kMaxSteps)) + " steps ahead");
             step(s, static_cast<long>(n));
           }, py::arg("t"), "Steps until the time is t (to the nearest step); t before the current time is an error.")
      .def_property_readonly("time", [](const PySim& s) { return s.get().time(); }, "t of the current state")
      .def_property_readonly("steps", [](const PySim& s) { return s.get().steps(); }, "steps taken")
      .def_property_readonly("dt", [](const PySim& s) { return s.get().fluid().params().dt; }, "the time step")
      .def_property_readonly("method", [](const PySim& s) { return std::string(to_string(s.get().fluid().params().method)); }, "eulerian, lagrangian, wcsph or isph")
      .def_property_readonly("particles_move", [](const PySim& s) { return s.get().fluid().particles_move(); }, "False on the fixed lattice (EPSPH)")
      .def_property_readonly("N", [](const PySim& s) { return s.get().fluid().size(); }, "number of particles")
      .def_property_readonly("nx", [](const PySim& s) { return s.get().fluid().lattice().nx; }, "lattice sites along x")
      .def_property_readonly("ny", [](const PySim& s) { return s.get().fluid().lattice().ny; }, "lattice sites along y")
      .def_property_readonly("dx", [](const PySim& s) { return s.get().fluid().lattice().dx; }, "lattice spacing along x")
      .def_property_readonly("dy", [](const PySim& s) { return s.get().fluid().lattice().dy; }, "lattice spacing along y")
      .def_property_readonly("h", [](const PySim& s) { return s.get().fluid().h(); }, "smoothing length h")
      .def_property_readonly("x", [](const PySim& s) { return view_of(s, s.get().fluid().x()); },
                             "particle positions (N x 2; on a lattice particle i + nx j)")
      .def_property_readonly("u", [](const PySim& s) { return view_of(s, s.get().fluid().u()); },
                             "velocity u^n (N x 2): u[:, 0].reshape(ny, nx) is u on the lattice, still a view")
      .def_property_readonly("p", [](const PySim& s) { return view_of(s, s.get().fluid().p()); }, "pressure (N)")
      .def_property_readonly("phi", [](const PySim& s) { return view_of(s, s.get().fluid().phi()); },
                             "projection methods: phi^n; WCSPH: density (N)")
      .def_property_readonly("volumes", [](const PySim& s) { return view_of(s, s.get().fluid().volumes()); }, "particle volumes (N)")
      .def_property_readonly("force", [](const PySim& s) { return view_of(s, s.get().force()); },
                             "force per unit volume of the last step on the particles, body + membranes (N x 2)")
      .def_property_readonly("membrane_count", [](const PySim& s) { return s.get().membranes().size(); }, "number of membranes")
      .def("markers", [](const PySim& s, int k) { return view_of(s, s.membrane(k).m.X); },
           py::arg("k") = 0, "marker positions X of membrane k (nb x 2)")
      .def("membrane_force", [](const PySim& s, int k) { return view_of(s, s.membrane(k).f); },
           py::arg("k") = 0, "force density f of membrane k at its markers (nb x 2)")
      .def("tension", [](const PySim& s, int k) { return view_of(s, s.membrane(k).T); },
           py::arg("k") = 0, "tension T of membrane k at its markers (nb)")
      .def("marker_velocity", [](const PySim& s, int k) { return view_of(s, s.membrane(k).U); },
           py::arg("k") = 0, "u(X) at the markers of membrane k after the last step (nb x 2)")
      .def("membrane", [](const PySim& s, int k) {
             const MembraneState& ms = s.membrane(k);
             MembraneDiagnostics D(ms.m.nb(), ms.m.L0());
             py::dict d = shape_dict(D.measure(ms.m.X));
             MembraneForce E = ms.force;
             E.fit_energy(ms.m.X);
             const MembraneEnergy e = E.energy();
             d["nb"] = ms.m.nb(), d["L0"] = ms.m.L0(), d["law"] = ms.m.mat.law, d["Es"] = ms.m.mat.Es, d["Eb"] = ms.m.mat.Eb;
             d["T0"] = ms.m.mat.Es, d["h_star"] = ms.h_star, d["fixed"] = ms.fixed;
             d["elastic_energy"] = e.total(), d["bending_energy"] = e.bending;
             d["iterations"] = ms.last.iterations;
             return d;
           }, py::arg("k") = 0, "membrane k's parameters and shape (area, centroid, rx, ry, length, elastic energy)")
      .def("shape", [](const PySim& s, int k) { return ellipse_fit(s.membrane(k).m.X); }, py::arg("k") = 0,
           "the ellipse fitted to membrane k by second moments: L, B, theta, deformation (sphib.ellipse_fit)")
      .def("angular_velocity", [](const PySim& s, int k) {
             const MembraneState& ms = s.membrane(k);
             return mean_angular_velocity(ms.m.X, ms.U, ellipse_fit(ms.m.X).centroid);
           }, py::arg("k") = 0, "mean angular velocity of membrane k's markers about its centroid (sphib.angular_velocity)")
      .def("kinetic_energy", [](const PySim& s) { return s.get().fluid().kinetic_energy(); }, "the fluid's kinetic energy")
      .def("max_div_u", [](const PySim& s) { return s.get().fluid().max_abs_divergence(); }, "the largest discrete divergence of u over the particles");
}

// Loading and running scenes.
void bind_running(py::module_& m) {
  m.def("load_scene", [](const std::filesystem::path& path, std::optional<py::dict> set) {
          auto s = std::make_unique<PyScene>();
          s->path = s->name = path.string();
          if (set) flatten(*set, "", s->overrides);
          s->validate();
          return s;
        }, py::arg("path"), py::arg("set") = py::none(),
        "Reads a scene file (str or os.PathLike) with overrides: load_scene('cases/membrane_oscillation.toml', "
        "set={'grid.nx': 32}).");
  m.def("run", &run, py::arg("scene"), py::arg_v("out", std::filesystem::path("out"), "'out'"), py::arg("log") = false,
        py::arg("restart") = py::none(),
        "Runs the scene with the library's loop into out (output.h5, .xdmf, diagnostics.csv, summary.json, "
        "checkpoint.h5); returns the summary as a dict. restart: a checkpoint to continue from. Ctrl-C ends the "
        "run after the current step with complete output, then raises KeyboardInterrupt.");
  m.def("scene_keys", [] { return py::list(py::module_::import("json").attr("loads")(scene_keys_json())); },
        "Every scene key as `sphib keys --json` lists it: a list of dicts with name, type, default, required, "
        "range, help.");
}

}  // namespace

PYBIND11_MODULE(sphib, m) {
  m.doc() = "sphib: immersed-boundary fluid-structure interaction with projection SPH (Python bindings)";
  m.attr("__version__") = SPHIB_VERSION;
  py::register_exception<SceneError>(m, "SceneError", PyExc_ValueError);
  py::register_exception<RunError>(m, "RunError", PyExc_RuntimeError);
  // Classes before the functions that take or return them, so that signatures name them.
  bind_membranes(m);
  bind_scene(m);
  bind_simulation(m);
  bind_running(m);
}
