// cdpowder_module.cpp — `import cdpowder`: the library from Python (pybind11). The runs go
// through the same functions as the command line (read_scene, make_world, run_simulation,
// RunFolder), so the same scene and seeds give the same numbers; errors arrive as exceptions
// with the command line's messages; a sphere's state is a NumPy view of the World's own arrays.
#include <fmt/format.h>
#include <toml++/toml.h>

#include <atomic>
#include <cdpowder/cdpowder.hpp>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>
#include <sstream>
#include <string>
#include <vector>

namespace py = pybind11;

namespace cdpowder::python {
namespace {

/// A Python value as the TOML text of a --set override ("key=value").
std::string override_text(const std::string& key, const py::handle& value) {
  std::string text;
  if (py::isinstance<py::bool_>(value)) {
    text = value.cast<bool>() ? "true" : "false";
  } else if (py::isinstance<py::int_>(value)) {
    text = std::to_string(value.cast<long long>());
  } else if (py::isinstance<py::float_>(value)) {
    text = py::repr(value).cast<std::string>();  // shortest exact form
    if (text.find_first_of(".eEn") == std::string::npos) text += ".0";
  } else if (py::isinstance<py::str>(value)) {
    text = "\"" + value.cast<std::string>() + "\"";
  } else if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value) ||
             py::isinstance<py::array>(value)) {
    // a vector key (system.gravity): a TOML array of its numbers
    const py::list items =
        py::module_::import("builtins")
            .attr("list")(py::isinstance<py::array>(value) ? value.attr("tolist")() : value);
    text = "[";
    for (std::size_t i = 0; i < items.size(); ++i) {
      const auto item = py::reinterpret_borrow<py::object>(items[i]);
      if (py::isinstance<py::bool_>(item) ||
          (!py::isinstance<py::int_>(item) && !py::isinstance<py::float_>(item))) {
        throw py::type_error("overrides[\"" + key + "\"][" + std::to_string(i) + "]: got " +
                             py::str(py::type::of(item)).cast<std::string>() +
                             ", expected a number");
      }
      text += std::string(i > 0 ? ", " : "") + py::repr(py::float_(item)).cast<std::string>();
    }
    text += "]";
  } else {
    throw py::type_error("overrides[\"" + key + "\"]: got " +
                         py::str(py::type::of(value)).cast<std::string>() +
                         ", expected a bool, an int, a float, a str or a list of numbers");
  }
  return key + "=" + text;
}

/// The value at a dotted key of a resolved scene, as Python sees it (numbers, bools, strings,
/// lists); KeyError when the scene has no such key.
py::object scene_value(const Scene& scene, const std::string& key) {
  const toml::table table = toml::parse(scene.effective_toml);
  const toml::node* node = table.at_path(key).node();
  if (node == nullptr || node->is_table()) {
    throw py::key_error(key + ": not a key of the scene (docs/config.md lists them)");
  }
  const auto value_of = [](const toml::node& n) -> py::object {
    if (const auto* v = n.as_boolean()) return py::bool_(v->get());
    if (const auto* v = n.as_integer()) return py::int_(v->get());
    if (const auto* v = n.as_floating_point()) return py::float_(v->get());
    if (const auto* v = n.as_string()) return py::str(v->get());
    return py::none();
  };
  if (const auto* array = node->as_array()) {
    py::list items;
    for (const toml::node& item : *array) items.append(value_of(item));
    return items;
  }
  return value_of(*node);
}

std::vector<SceneOverride> overrides_of(const py::dict& overrides) {
  std::vector<SceneOverride> out;
  for (const auto& [key, value] : overrides) {
    const auto name = py::str(key).cast<std::string>();
    SceneOverride& edit = out.emplace_back(override_text(name, value));
    edit.origin = "overrides[\"" + name + "\"]";  // the Python argument, not --set
  }
  return out;
}

/// The scene's text the library wrote (the resolved TOML, read again with a command's demands),
/// named in messages as the scene, never by a line of a text the user did not write.
constexpr const char* kResolvedScene = "the scene";

/// Runs `read`; a ConfigError's issues placed in the resolved scene's text lose their places.
template <typename Read>
Scene without_places_in_resolved_text(Read&& read) {
  try {
    return read();
  } catch (const ConfigError& error) {
    std::vector<ConfigIssue> issues = error.issues();
    for (ConfigIssue& issue : issues) {
      if (issue.file != kResolvedScene) continue;
      issue.line = 0;
      issue.column = 0;
    }
    throw ConfigError(std::move(issues));
  }
}

/// A scene as read, with where it came from (a compaction reads it again with its demands).
struct PyScene {
  Scene scene;
  std::filesystem::path base_dir;

  /// A scene built in code: every key given as a --set override on an empty file, relative
  /// paths from the working folder.
  static PyScene from_keys(const py::dict& keys) {
    PyScene s;
    s.base_dir = std::filesystem::current_path();
    s.scene = read_scene_text("", "Scene.from_keys", overrides_of(keys), s.base_dir);
    return s;
  }

  static PyScene from_toml(const std::filesystem::path& path, const py::dict& overrides) {
    PyScene s;
    s.scene = read_scene(path, overrides_of(overrides));
    std::error_code error;
    s.base_dir = std::filesystem::absolute(path, error).parent_path();
    return s;
  }

  /// The same scene with more overrides, checked as the command line checks them.
  [[nodiscard]] PyScene with(const py::dict& overrides, const SceneReadOptions& how = {}) const {
    PyScene s;
    s.scene = without_places_in_resolved_text([&] {
      return read_scene_text(scene.effective_toml, kResolvedScene, overrides_of(overrides),
                             base_dir, how);
    });
    s.scene.source = scene.source;
    s.base_dir = base_dir;
    return s;
  }
};

/// A view of `values` (n × 3 doubles, a std::vector<Vec3>) that keeps `owner` alive.
py::array_t<double> vec3_view(std::vector<Vec3>& values, const py::object& owner) {
  static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 is three packed doubles");
  return py::array_t<double>(
      {static_cast<py::ssize_t>(values.size()), py::ssize_t{3}},
      {static_cast<py::ssize_t>(sizeof(Vec3)), static_cast<py::ssize_t>(sizeof(double))},
      reinterpret_cast<double*>(values.data()), owner);
}

py::array_t<double> double_view(std::vector<double>& values, const py::object& owner) {
  return py::array_t<double>({static_cast<py::ssize_t>(values.size())},
                             {static_cast<py::ssize_t>(sizeof(double))}, values.data(), owner);
}

/// A world with the step workspace that goes with it (the warm start, the candidate lists):
/// continuing a run continues both.
struct Engine {
  World world;
  StepWorkspace work{1};
  RunState state;
  /// the scene it was made from or last run with: World.step and World.run step with its
  /// solver and run settings, World.save stores it
  PyScene scene;
  double initial_porosity = 0.0;  ///< when it was made [-]
  bool in_use = false;            ///< a run steps it: a second run on it is refused (EngineInUse)
  /// the run is stepping it without the GIL (not paused in its callback): the World's
  /// computed properties refuse to read it meanwhile (idle)
  std::atomic<bool> stepping{false};
};

/// `engine`, when no run is stepping it. A property read from another Python thread while a
/// run steps the World would read contacts being rebuilt: refused (a run's own callback reads
/// it paused, between two steps).
const Engine& idle(const Engine& engine) {
  if (engine.stepping.load()) {
    throw std::runtime_error(
        "this World is being stepped by a run on another thread: read it from the run's "
        "callback, or after the run");
  }
  // the engine lives in a Python object, never in a temporary
  return engine;  // NOLINT(bugprone-return-const-ref-from-parameter)
}

/// Holds an engine for one run. Python threads may share a World, and a callback is handed
/// its own World: a second run on it while the first steps would corrupt both, so it is
/// refused (checked and set under the GIL).
class EngineInUse {
 public:
  explicit EngineInUse(Engine& engine) : engine_(engine) {
    if (engine_.in_use) {
      throw std::runtime_error(
          "this World is in use by a run (another thread's, or the one whose callback this is): "
          "wait for it to end, or run on a copy");
    }
    engine_.in_use = true;
  }

  ~EngineInUse() { engine_.in_use = false; }

  EngineInUse(const EngineInUse&) = delete;
  EngineInUse& operator=(const EngineInUse&) = delete;
  EngineInUse(EngineInUse&&) = delete;
  EngineInUse& operator=(EngineInUse&&) = delete;

 private:
  Engine& engine_;
};

/// A property of World: the n × 3 view of one of the spheres' vectors.
auto body_vectors(std::vector<Vec3> Bodies::*field) {
  return [field](const py::object& self) {
    return vec3_view(self.cast<Engine&>().world.bodies.*field, self);
  };
}

/// A property of World: the view of one of the spheres' numbers.
auto body_scalars(std::vector<double> Bodies::*field) {
  return [field](const py::object& self) {
    return double_view(self.cast<Engine&>().world.bodies.*field, self);
  };
}

/// The contacts of the engine's last step as a dict of NumPy arrays (copies).
py::dict contacts_of(const Engine& running) {
  const Engine& engine = idle(running);
  std::vector<long long> a;
  std::vector<long long> b;
  std::vector<double> normal;
  std::vector<double> force;
  std::vector<double> normal_force;
  std::vector<double> tangential;
  std::vector<double> rolling;
  std::vector<double> twisting;
  std::vector<double> gap;
  std::vector<bool> closed;
  std::vector<bool> cohesive;
  for_each_contact(engine.work.contacts, [&](const ContactView& c) {
    // a wall contact: a = −1 for the bottom wall, −2 for the piston (contacts.csv's codes)
    a.push_back(c.is_pair() ? static_cast<long long>(c.a)
                            : (*c.wall == WallKind::Bottom ? -1 : -2));
    b.push_back(static_cast<long long>(c.b));
    const Vec3 total = c.action->normal_force * c.normal + c.action->tangential_force;
    normal.insert(normal.end(), {c.normal.x(), c.normal.y(), c.normal.z()});
    force.insert(force.end(), {total.x(), total.y(), total.z()});
    normal_force.push_back(c.action->normal_force);
    const ContactAction& x = *c.action;
    tangential.insert(tangential.end(),
                      {x.tangential_force.x(), x.tangential_force.y(), x.tangential_force.z()});
    rolling.insert(rolling.end(),
                   {x.rolling_torque.x(), x.rolling_torque.y(), x.rolling_torque.z()});
    twisting.push_back(x.twisting_torque);
    gap.push_back(c.gap);
    closed.push_back(c.closed());
    cohesive.push_back(c.cohesive);
  });
  const auto n = static_cast<py::ssize_t>(a.size());
  py::dict out;
  out["a"] = py::array_t<long long>(n, a.data());
  out["b"] = py::array_t<long long>(n, b.data());
  out["normal"] = py::array_t<double>({n, py::ssize_t{3}}, normal.data());
  out["force"] = py::array_t<double>({n, py::ssize_t{3}}, force.data());
  out["normal_force"] = py::array_t<double>(n, normal_force.data());
  out["tangential_force"] = py::array_t<double>({n, py::ssize_t{3}}, tangential.data());
  out["rolling_torque"] = py::array_t<double>({n, py::ssize_t{3}}, rolling.data());
  out["twisting_torque"] = py::array_t<double>(n, twisting.data());
  out["gap"] = py::array_t<double>(n, gap.data());
  py::array_t<bool> closed_array(n);
  py::array_t<bool> cohesive_array(n);
  for (py::ssize_t k = 0; k < n; ++k) {
    closed_array.mutable_at(k) = closed[static_cast<std::size_t>(k)];
    cohesive_array.mutable_at(k) = cohesive[static_cast<std::size_t>(k)];
  }
  out["closed"] = closed_array;
  out["cohesive"] = cohesive_array;
  return out;
}

/// What a run returns to Python.
struct Result {
  std::shared_ptr<Engine> engine;
  RunResult run;
  Scene scene;
  double initial_porosity = 0.0;

  [[nodiscard]] StressTensors stress() const {
    const Engine& e = idle(*engine);
    return stress_tensors(e.work.contacts, packing_volume(e.world));
  }

  [[nodiscard]] py::dict summary() const {
    const Engine& e = idle(*engine);
    const std::string json =
        run_summary_json(summarise_run(scene, e.world, e.work.contacts, run, initial_porosity));
    return py::module_::import("json").attr("loads")(json);
  }
};

/// How often a run asks Python for a Ctrl-C: the GIL is taken for it, and another Python
/// thread may hold it for up to its switch interval (5 ms), so not after every pass [s].
constexpr double kSignalCheckSeconds = 0.02;

/// The callback's word on the run: its result judged by Python's own truth (None goes on), an
/// exception (also one a __bool__ raises) kept to be raised when the outputs are written.
struct CallbackVerdict {
  bool stop = false;
  std::optional<py::error_already_set> error;

  void judge(const py::object& callback, const py::object& world, const StepDiagnostics& step) {
    try {
      const py::object verdict = callback(world, py::cast(step));
      if (verdict.is_none()) return;
      const int truth = PyObject_IsTrue(verdict.ptr());
      if (truth < 0) throw py::error_already_set();
      stop = truth == 0;
    } catch (py::error_already_set& e) {
      error = std::move(e);
      stop = true;
    }
  }
};

/// The fault a callback left in the World through its views (a radius of 0, a NaN), as the
/// run's fault: the run stops there instead of stepping on as if nothing happened.
std::optional<RunFault> fault_after_callback(const World& world) {
  const std::optional<std::string> problem = world_problem(world);
  if (!problem) return std::nullopt;
  RunFault fault;
  fault.quantity = "state written by the callback";
  fault.step = world.step;
  fault.time = world.time;
  fault.message = fmt::format("after the callback at step {} (t = {:.6g} t0): {}", world.step,
                              world.time, *problem);
  return fault;
}

/// Raises cdpowder.RunFailed (a RuntimeError) for a run a fault stopped, its outputs written;
/// the exception's `result` is the run's Result.
[[noreturn]] void raise_run_failed(const py::object& run_failed, const RunFault& fault,
                                   const py::object& result) {
  const py::object error = run_failed(fault.message);
  error.attr("result") = result;
  error.attr("quantity") = fault.quantity;
  error.attr("sphere") = fault.body >= 0 ? py::object(py::int_(fault.body)) : py::none();
  error.attr("other_sphere") = fault.other >= 0 ? py::object(py::int_(fault.other)) : py::none();
  error.attr("step") = fault.step;
  error.attr("time") = fault.time;
  error.attr("value") = fault.value;
  PyErr_SetObject(run_failed.ptr(), error.ptr());
  throw py::error_already_set();
}

/// Runs `scene` on `engine` to its end, calling `callback(world, step)` every `every` steps
/// (a false result stops the run) and checking for Ctrl-C every kSignalCheckSeconds; writes the
/// command line's files into `out` when given, holding the folder's run lock as the command
/// line does. The GIL is released while the engine steps and taken back for the callback. A
/// Ctrl-C ends the run as interrupted (outputs written) and then raises KeyboardInterrupt; an
/// exception in the callback is raised once the outputs are written; a fault raises RunFailed.
Result run(const Scene& scene, std::shared_ptr<Engine> engine, const py::object& callback,
           int every, const std::optional<std::filesystem::path>& out, double initial_porosity,
           const std::function<bool()>& enough = {}, bool check = true) {
  if (every < 1) throw py::value_error("every: got " + std::to_string(every) + ", expected ≥ 1");
  std::optional<FolderLock> lock;
  std::optional<RunFolder> files;
  if (out) {
    std::filesystem::create_directories(*out);
    lock.emplace(run_lock_file(*out), "another cdpowder run");  // before the folder is touched
    files = RunFolder::begin(*out, scene, engine->world, engine->work.contacts, {});
  }
  bool interrupted_by_signal = false;
  CallbackVerdict verdict;
  std::optional<RunFault> callback_fault;
  std::int64_t steps = 0;
  const py::object world_object = py::cast(engine);
  // called without the GIL: only the callback takes it
  const StepObserver observer = [&](const World& world, const StepReport& report, double) {
    if (files) files->after_step(world, report, engine->work.contacts);
    ++steps;
    if (callback.is_none() || steps % every != 0 || verdict.stop) return;
    {
      engine->stepping.store(false);  // paused: other threads may read the World now
      const py::gil_scoped_acquire gil;
      verdict.judge(callback, world_object, report.diagnostics);
      engine->stepping.store(true);  // still holding the GIL: no reader is in between
    }
    callback_fault = fault_after_callback(world);
    if (callback_fault) verdict.stop = true;
  };
  auto last_check = std::chrono::steady_clock::now();
  bool reached = false;  // the caller's end (steps, time) rather than a stop
  const StopRequest stop = [&] {
    if (interrupted_by_signal || verdict.stop) return true;
    // changes only with a step (the observer), so never inside a step's solve
    if (enough && enough()) {
      reached = true;
      return true;
    }
    const auto now = std::chrono::steady_clock::now();
    if (std::chrono::duration<double>(now - last_check).count() < kSignalCheckSeconds) {
      return false;
    }
    last_check = now;
    const py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) interrupted_by_signal = true;
    return interrupted_by_signal;
  };
  Result result;
  {
    // while the GIL is released, the World's computed properties refuse to read it
    struct Stepping {
      explicit Stepping(Engine& e) : engine(e) { engine.stepping.store(true); }

      ~Stepping() { engine.stepping.store(false); }

      Stepping(const Stepping&) = delete;
      Stepping& operator=(const Stepping&) = delete;
      Stepping(Stepping&&) = delete;
      Stepping& operator=(Stepping&&) = delete;
      Engine& engine;
    } const stepping(*engine);

    const py::gil_scoped_release released;
    result.run = run_simulation(engine->world, engine->work, scene.step, scene.run, engine->state,
                                observer, stop);
    if (callback_fault && !result.run.fault) result.run.fault = callback_fault;
    if (files) {
      files->finish(scene, engine->world, engine->work, engine->state, result.run,
                    initial_porosity);
    }
  }
  result.engine = engine;
  result.scene = scene;
  result.initial_porosity = initial_porosity;
  // World.run's end reached: a run that ended as asked, not an interrupted one
  if (reached && !interrupted_by_signal && !verdict.stop) result.run.interrupted = false;
  if (verdict.error) throw std::move(*verdict.error);
  if (interrupted_by_signal) throw py::error_already_set();  // the KeyboardInterrupt
  if (result.run.fault && check) {
    raise_run_failed(py::module_::import("cdpowder").attr("RunFailed"), *result.run.fault,
                     py::cast(result));
  }
  return result;
}

std::shared_ptr<Engine> fresh_engine(const PyScene& scene) {
  auto engine = std::make_shared<Engine>();
  engine->world = make_world(scene.scene, [] { return PyErr_CheckSignals() != 0; });
  engine->work = StepWorkspace(scene.scene.step.solver.seed);
  engine->scene = scene;
  engine->initial_porosity = porosity(engine->world);
  return engine;
}

using Doubles = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// "(4, 2)": an array's shape as NumPy prints it.
std::string shape_text(const py::array& a) {
  return py::str(py::tuple(py::cast(std::vector<py::ssize_t>(a.shape(), a.shape() + a.ndim()))))
      .cast<std::string>();
}

/// `values` as n × `columns` finite numbers (columns 0: a vector of n), each at least
/// `lower` (exclusive when `above`); a ValueError names the argument, the entry and the rule.
Doubles checked_array(const std::string& name, const py::object& values, py::ssize_t n,
                      py::ssize_t columns, double lower = -std::numeric_limits<double>::infinity(),
                      bool above = false) {
  Doubles a = Doubles::ensure(values);
  if (!a) throw py::value_error(name + ": expected an array of numbers");
  const bool vector = columns == 0;
  if (a.ndim() != (vector ? 1 : 2) || a.shape(0) != n || (!vector && a.shape(1) != columns)) {
    const std::string wanted =
        vector ? fmt::format("({},)", n) : fmt::format("({}, {})", n, columns);
    throw py::value_error(
        fmt::format("{}: got an array of shape {}, expected {}", name, shape_text(a), wanted));
  }
  const double* data = a.data();
  const py::ssize_t width = vector ? 1 : columns;
  for (py::ssize_t k = 0; k < a.size(); ++k) {
    const double v = data[k];
    const bool ok = std::isfinite(v) && (above ? v > lower : v >= lower);
    if (ok) continue;
    const std::string where =
        vector ? fmt::format("[{}]", k) : fmt::format("[{}, {}]", k / width, k % width);
    const std::string rule = std::isinf(lower) ? "a finite number"
                             : above           ? fmt::format("a finite number > {}", lower)
                                               : fmt::format("a finite number ≥ {}", lower);
    throw py::value_error(fmt::format("{}{}: got {}, expected {}", name, where, v, rule));
  }
  return a;
}

/// The world of `scene` around spheres given as arrays (positions n × 3 [R], radii n [R],
/// optional velocities n × 3 [R/t0], angular velocities n × 3 [1/t0], fixed n booleans),
/// with the scene's density, cell, walls and piston: make_world's, the spheres excepted.
std::shared_ptr<Engine> world_from_arrays(const PyScene& scene, const py::object& positions,
                                          const py::object& radii, const py::object& velocities,
                                          const py::object& angular_velocities,
                                          const py::object& fixed) {
  const Doubles r = Doubles::ensure(radii);
  if (!r || r.ndim() != 1) throw py::value_error("radii: expected a vector of n numbers");
  const py::ssize_t n = r.shape(0);
  if (n == 0) throw py::value_error("radii: got 0 spheres, expected at least 1");
  const Doubles x = checked_array("positions", positions, n, 3);
  checked_array("radii", r, n, 0, 0.0, /*above=*/true);  // r: converted once
  SceneReadOptions how;
  how.spheres_from_caller = true;
  const Scene resolved = scene.with({}, how).scene;
  Bodies spheres;
  const auto is_fixed = fixed.is_none() ? std::vector<bool>(static_cast<std::size_t>(n), false)
                                        : fixed.cast<std::vector<bool>>();
  if (is_fixed.size() != static_cast<std::size_t>(n))
    throw py::value_error(fmt::format("fixed: got {} values, expected {}", is_fixed.size(), n));
  for (py::ssize_t i = 0; i < n; ++i) {
    spheres.add_sphere(Vec3(x.at(i, 0), x.at(i, 1), x.at(i, 2)), r.at(i), resolved.system.density,
                       is_fixed[static_cast<std::size_t>(i)]);
  }
  const auto set_vectors = [&](const char* name, const py::object& values,
                               std::vector<Vec3>& field) {
    if (values.is_none()) return;
    const Doubles v = checked_array(name, values, n, 3);
    for (py::ssize_t i = 0; i < n; ++i) field[i] = Vec3(v.at(i, 0), v.at(i, 1), v.at(i, 2));
  };
  set_vectors("velocities", velocities, spheres.velocity);
  set_vectors("angular_velocities", angular_velocities, spheres.angular_velocity);
  auto engine = std::make_shared<Engine>();
  engine->world = make_world(resolved, std::move(spheres));
  // what the arrays' own checks leave: centres beyond the coordinates doubles resolve
  if (const std::optional<std::string> problem = world_problem(engine->world)) {
    throw py::value_error(*problem);
  }
  engine->work = StepWorkspace(resolved.step.solver.seed);
  engine->scene = PyScene{resolved, scene.base_dir};
  engine->initial_porosity = porosity(engine->world);
  return engine;
}

/// A compaction or a simulation: on `world` (a Result's or a deposit's engine, continued: its
/// piston gets this scene's push) or on the scene's own spheres.
Result start(const PyScene& scene, const py::object& world, const py::object& callback, int every,
             const std::optional<std::filesystem::path>& out) {
  const std::shared_ptr<Engine> engine =
      world.is_none() ? fresh_engine(scene) : world.cast<std::shared_ptr<Engine>>();
  // before anything of the World changes: a run in progress keeps it
  const EngineInUse busy(*engine);
  if (!world.is_none()) {
    Piston& piston = engine->world.walls.piston;
    piston.force = scene.scene.piston.push(engine->world.box.area());
    engine->state = RunState{};  // a new run on the packing as it is
  }
  engine->scene = scene;
  return run(scene.scene, engine, callback, every, out, porosity(engine->world));
}

/// World.run: the engine continued with its scene's settings until `steps` more steps, the
/// first step at or after time `until`, or (`until_blocked`, by default the scene's
/// run.until_blocked) the blocked state or run.max_duration, whichever comes first. The blocked
/// test runs as the command line's does, so a compaction stepped in any pieces ends on the
/// bits of `cdpowder compact` (a run stopped and continued is the run never stopped,
/// run_loop.hpp).
Result run_world(const std::shared_ptr<Engine>& engine, std::optional<std::int64_t> steps,
                 std::optional<double> until, std::optional<bool> blocked,
                 const py::object& callback, int every,
                 const std::optional<std::filesystem::path>& out, bool check) {
  const EngineInUse busy(*engine);
  const bool until_blocked = blocked.value_or(engine->scene.scene.run.until_blocked);
  if (!steps && !until && !until_blocked) {
    throw py::value_error(
        "run: give steps=, until= or until_blocked=True (the world's scene does not run until "
        "blocked)");
  }
  if (steps && *steps < 1) {
    throw py::value_error(fmt::format("steps: got {}, expected ≥ 1", *steps));
  }
  const World& world = engine->world;
  if (until && !(std::isfinite(*until) && *until > world.time)) {
    throw py::value_error(
        fmt::format("until: got {}, expected a time after the world's, {} t0", *until, world.time));
  }
  Scene scene = engine->scene.scene;
  if (until_blocked && !scene.piston.enabled) {
    throw py::value_error(
        "until_blocked: the world's scene has no piston (piston.enabled = false); a run ends "
        "at its blocked state only under a piston");
  }
  scene.run.until_blocked = until_blocked;
  // without the blocked state, the run's own duration does not end it: steps= and until= do
  if (!until_blocked) scene.run.duration = std::numeric_limits<double>::infinity();
  const std::int64_t first_step = world.step;
  const std::function<bool()> enough = [&, first_step] {
    return (steps && world.step - first_step >= *steps) || (until && world.time >= *until);
  };
  return run(scene, engine, callback, every, out, engine->initial_porosity, enough, check);
}

/// The World of a state file's bytes (a .cdps file, or a pickle's), with the scene it holds.
std::shared_ptr<Engine> engine_from_state(SavedRun saved, const std::filesystem::path& base_dir) {
  auto engine = std::make_shared<Engine>();
  SceneReadOptions how;
  how.spheres_from_caller = true;  // the spheres are the file's
  engine->scene.scene = without_places_in_resolved_text(
      [&] { return read_scene_text(saved.scene_toml, kResolvedScene, {}, base_dir, how); });
  engine->scene.scene.effective_toml = saved.scene_toml;
  engine->scene.base_dir = base_dir;
  engine->work = StepWorkspace(engine->scene.scene.step.solver.seed);
  const Scene& scene = engine->scene.scene;
  restore_run(std::move(saved), scene.run, scene.step.solver.dt, engine->world, engine->work,
              engine->state);
  engine->initial_porosity = porosity(engine->world);
  return engine;
}

/// The n × 3 array of `values` (a copy).
py::array_t<double> vec3_copy(const std::vector<Vec3>& values) {
  py::array_t<double> out({static_cast<py::ssize_t>(values.size()), py::ssize_t{3}});
  auto view = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < values.size(); ++i) {
    for (py::ssize_t k = 0; k < 3; ++k) view(static_cast<py::ssize_t>(i), k) = values[i][k];
  }
  return out;
}

/// The last step's loads on every sphere: contacts alone, or with the external force and
/// torque and the weight m g of a free sphere (`total`).
SphereLoads loads_of(const Engine& running, bool total) {
  const Engine& engine = idle(running);
  const Bodies& bodies = engine.world.bodies;
  SphereLoads loads = sphere_contact_loads(engine.work.contacts, bodies.size());
  if (!total) return loads;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    loads.force[i] += bodies.external_force[i];
    if (bodies.inverse_mass[i] > 0.0)
      loads.force[i] += engine.world.gravity / bodies.inverse_mass[i];
    loads.torque[i] += bodies.external_torque[i];
  }
  return loads;
}

/// ConfigError as cdpowder.ConfigError (a ValueError), Interrupted as KeyboardInterrupt.
void bind_errors(py::module_& m) {
  // named as the package names it (cdpowder.ConfigError), not as cdpowder._core's; kept by the
  // module alone (a static object would outlive the interpreter)
  m.attr("ConfigError") = py::reinterpret_steal<py::object>(PyErr_NewExceptionWithDoc(
      "cdpowder.ConfigError", "Bad input: the message names the key, the value and what is allowed",
      PyExc_ValueError, nullptr));
  // a fault stopped the run (the command line's exit 3); its outputs are written, and the
  // exception's `result` is the run's Result
  m.attr("RunFailed") = py::reinterpret_steal<py::object>(
      PyErr_NewExceptionWithDoc("cdpowder.RunFailed",
                                "A fault stopped the run (a state no physical run reaches); "
                                "the outputs are written and `result` holds the run",
                                PyExc_RuntimeError, nullptr));
  // pybind11 takes the translator as void(std::exception_ptr): by value
  py::register_exception_translator(
      [](std::exception_ptr p) {  // NOLINT(performance-unnecessary-value-param)
        try {
          if (p) std::rethrow_exception(p);
        } catch (const ConfigError& e) {
          const py::object error = py::module_::import("cdpowder._core").attr("ConfigError");
          PyErr_SetString(error.ptr(), e.what());
        } catch (const Interrupted& e) {
          PyErr_SetString(PyExc_KeyboardInterrupt, e.what());
        }
      });
}

/// cdpowder.Scene: read, built from keys, overridden.
void bind_scene(py::module_& m) {
  py::class_<PyScene>(m, "Scene", "A scene (docs/config.md), read and checked")
      .def_static("from_toml", &PyScene::from_toml, py::arg("path"),
                  py::arg("overrides") = py::dict(),
                  "The scene of a TOML file with --set style overrides {\"section.key\": value}")
      .def_static("from_keys", &PyScene::from_keys, py::arg("keys"),
                  "A scene built in code from {\"section.key\": value} (docs/config.md); keys "
                  "left out take their defaults")
      .def(
          "with_overrides",
          [](const PyScene& s, const py::dict& overrides) { return s.with(overrides); },
          py::arg("overrides"), "The same scene with more overrides")
      .def_property_readonly(
          "toml", [](const PyScene& s) { return s.scene.effective_toml; },
          "The fully resolved scene as TOML")
      .def_property_readonly(
          "seed", [](const PyScene& s) { return s.scene.step.solver.seed; },
          "solver.seed, the seed of the pass-order stream")
      .def(
          "__getitem__",
          [](const PyScene& s, const std::string& key) { return scene_value(s.scene, key); },
          py::arg("key"),
          "The resolved value of a key (\"contact.mu\"): a number, bool, str or list")
      .def("__repr__", [](const PyScene& s) {
        return "<cdpowder.Scene from " + s.scene.source.string() + ">";
      });
}

/// World's state: the spheres as NumPy views and what is measured of them.
void bind_world_state(py::class_<Engine, std::shared_ptr<Engine>>& world) {
  world
      .def_static("from_arrays", &world_from_arrays, py::arg("scene"), py::arg("positions"),
                  py::arg("radii"), py::arg("velocities") = py::none(),
                  py::arg("angular_velocities") = py::none(), py::arg("fixed") = py::none(),
                  "A world of the scene's cell, walls and piston (at rest on the highest sphere "
                  "plus piston.start_gap, unless piston.height) around spheres given as arrays: "
                  "positions n × 3 [R], radii n [R], optionally velocities and "
                  "angular_velocities n × 3, fixed n booleans; the scene's [deposition] or "
                  "[particles] is not used. Compact or simulate it with world=")
      .def_property_readonly("positions", body_vectors(&Bodies::position),
                             "Sphere centres, n × 3 [R] (a view: no copy)")
      .def_property_readonly("velocities", body_vectors(&Bodies::velocity), "n × 3 [R/t0] (a view)")
      .def_property_readonly("angular_velocities", body_vectors(&Bodies::angular_velocity),
                             "n × 3 [1/t0] (a view)")
      .def_property_readonly("radii", body_scalars(&Bodies::radius), "n [R] (a view)")
      .def_property_readonly(
          "time", [](const Engine& e) { return idle(e).world.time; }, "Simulated time [t0]")
      .def_property_readonly(
          "step_count", [](const Engine& e) { return idle(e).world.step; },
          "Steps taken since the world was made")
      .def_property_readonly(
          "scene", [](const Engine& e) { return idle(e).scene; },
          "The scene the world steps with: the one it was made from or last run with")
      .def("contacts", &contacts_of,
           "The last step's contacts, contacts.csv's columns as a dict of arrays: a, b (−1 "
           "bottom wall, −2 piston), normal (n × 3), normal_force, tangential_force (n × 3), "
           "rolling_torque (n × 3), twisting_torque, force (normal and tangential, n × 3), gap, "
           "cohesive, closed")
      .def(
          "__len__", [](const Engine& e) { return idle(e).world.bodies.size(); },
          "The number of spheres");
}

/// World as an engine: stepping, saving and pickling.
void bind_world_engine(py::class_<Engine, std::shared_ptr<Engine>>& world) {
  world
      .def(
          "step",
          [](const std::shared_ptr<Engine>& e, std::int64_t n) {
            const Result r =
                run_world(e, n, std::nullopt, std::nullopt, py::none(), 1, std::nullopt, true);
            return r.run.last.diagnostics;
          },
          py::arg("n") = 1,
          "Takes n steps (fewer if the scene runs until blocked and the world blocks) with the "
          "scene's settings; returns the last step's StepDiagnostics")
      .def("run", &run_world, py::arg("steps") = py::none(), py::arg("until") = py::none(),
           py::arg("until_blocked") = py::none(), py::arg("callback") = py::none(),
           py::arg("every") = 1, py::arg("out") = py::none(), py::arg("check") = true,
           "Steps on with the scene's settings until `steps` more steps, the first step at or "
           "after time `until` [t0], or (until_blocked, by default the scene's "
           "run.until_blocked) the blocked state or run.max_duration, whichever comes first; "
           "the same bits as the command line. callback(world, step) every `every` steps, "
           "False stops; `out`: write the command line's files; a fault raises RunFailed "
           "unless check=False. Returns a Result")
      .def(
          "save",
          [](const Engine& e, const std::filesystem::path& path) {
            const Engine& engine = idle(e);
            save_state(path, engine.scene.scene.effective_toml, engine.world, engine.work,
                       engine.state);
          },
          py::arg("path"),
          "Writes the bit-exact state (a .cdps file, as a checkpoint): cdpowder.load(path) "
          "continues it with the same bits as a run never stopped")
      .def(py::pickle(
          [](const Engine& e) {
            const Engine& engine = idle(e);
            return py::make_tuple(py::bytes(encode_state(engine.scene.scene.effective_toml,
                                                         engine.world, engine.work, engine.state)),
                                  engine.scene.base_dir.string());
          },
          [](const py::tuple& t) {
            if (t.size() != 2) throw py::value_error("not a pickled cdpowder.World");
            return engine_from_state(decode_state(t[0].cast<std::string>(), "the pickle"),
                                     t[1].cast<std::string>());
          }));
}

/// World's measures of the last step: loads, stress, gauges, piston and porosity.
void bind_world_measures(py::class_<Engine, std::shared_ptr<Engine>>& world) {
  world
      .def(
          "contact_forces", [](const Engine& e) { return vec3_copy(loads_of(e, false).force); },
          "n × 3: each sphere's sum of its contacts' forces in the last step [F_coh]")
      .def(
          "contact_torques", [](const Engine& e) { return vec3_copy(loads_of(e, false).torque); },
          "n × 3: each sphere's sum of its contacts' torques about its centre [F_coh R]")
      .def(
          "forces", [](const Engine& e) { return vec3_copy(loads_of(e, true).force); },
          "n × 3: each sphere's total force in the last step: its contacts', its external force "
          "and, for a free sphere, its weight m g [F_coh]")
      .def(
          "torques", [](const Engine& e) { return vec3_copy(loads_of(e, true).torque); },
          "n × 3: each sphere's total torque: its contacts' and its external torque [F_coh R]")
      .def(
          "stress",
          [](const Engine& e) {
            const Engine& engine = idle(e);
            const StressTensors t =
                stress_tensors(engine.work.contacts, packing_volume(engine.world));
            py::dict out;
            out["sigma"] = Eigen::Matrix3d(t.total);
            out["sigma_plus"] = Eigen::Matrix3d(t.compressive);
            out["sigma_minus"] = Eigen::Matrix3d(t.tensile);
            return out;
          },
          "The stress of the last step's contact forces: {\"sigma\", \"sigma_plus\", "
          "\"sigma_minus\"}, 3 × 3 [F_coh/R²] (physics.md §11)")
      .def_property_readonly(
          "last_step",
          [](const Engine& e) -> py::object {
            const Engine& engine = idle(e);
            if (engine.state.result.steps == 0) return py::none();
            return py::cast(engine.state.result.last.diagnostics);
          },
          "The last step's StepDiagnostics (its accuracy gauges), or None before a step")
      .def_property_readonly(
          "piston_height", [](const Engine& e) { return idle(e).world.walls.piston.height; },
          "Height of the piston's lower face Z_P [R]")
      .def_property_readonly(
          "porosity", [](const Engine& e) { return porosity(idle(e).world); },
          "E = 1 − (volume of the spheres) / (cell area × Z_P): the paper's porosity")
      .def_property_readonly(
          "coordination_number",
          [](const Engine& e) {
            const Engine& i = idle(e);
            return coordination_number(i.work.contacts, i.world.bodies.size());
          },
          "Mean number of force-carrying contacts a sphere has in the last step");
}

/// cdpowder.StepDiagnostics and cdpowder.World (the spheres as NumPy views).
void bind_world(py::module_& m) {
  py::class_<StepDiagnostics>(m, "StepDiagnostics", "The measures and gauges of one step")
      .def_readonly("contacts", &StepDiagnostics::contacts,
                    "Candidate contacts of the step, pairs and walls")
      .def_readonly("closed_contacts", &StepDiagnostics::closed_contacts,
                    "Contacts carrying force (R_n + F_c > 0)")
      .def_readonly("cohesive_contacts", &StepDiagnostics::cohesive_contacts,
                    "Cohesion-active contacts")
      .def_readonly("mean_overlap", &StepDiagnostics::mean_overlap,
                    "Mean overlap of the closed contacts after the step [R] (physics.md §17: "
                    "≤ 1e-3)")
      .def_readonly("max_overlap", &StepDiagnostics::max_overlap,
                    "Largest overlap of any contact after the step [R]")
      .def_readonly("kinetic_energy", &StepDiagnostics::kinetic_energy,
                    "Σ ½ m v² + ½ I ω² of the spheres and ½ M_P V_P² of the piston [F_coh R]")
      .def_readonly("rms_speed", &StepDiagnostics::rms_speed,
                    "Mass-weighted RMS sphere speed [R/t0]")
      .def_readonly("piston_imbalance", &StepDiagnostics::piston_imbalance,
                    "The piston's force balance: the spheres' push on it minus its load, in "
                    "absolute value, over the load (0 without a load)")
      .def_readonly("max_net_force", &StepDiagnostics::max_net_force,
                    "Largest net force (and torque / radius) on a free sphere in the step "
                    "[F_coh]: ≈ 0 in a static packing (physics.md §17)");

  py::class_<Engine, std::shared_ptr<Engine>> world(
      m, "World", "Spheres, walls and piston, with the solver's memory of the last step");
  bind_world_state(world);
  bind_world_engine(world);
  bind_world_measures(world);
}

/// cdpowder.Result: the end of a run, its stress and summary.
void bind_result(py::module_& m) {
  py::class_<Result>(m, "Result", "The end of a run")
      .def_property_readonly(
          "world", [](const Result& r) { return r.engine; },
          "The World at the run's end, ready to step on")
      .def_property_readonly(
          "porosity", [](const Result& r) { return porosity(idle(*r.engine).world); },
          "The porosity E at the run's end")
      .def_property_readonly(
          "blocked", [](const Result& r) { return r.run.blocked; },
          "Whether the run ended at the blocked state (physics.md §9)")
      .def_property_readonly(
          "interrupted", [](const Result& r) { return r.run.interrupted; },
          "Whether a stop (Ctrl-C, a callback's False) ended the run before its end")
      .def_property_readonly(
          "steps", [](const Result& r) { return r.run.steps; },
          "Steps of the run so far (of every World.run call since the run began)")
      .def_property_readonly(
          "sigma", [](const Result& r) { return Eigen::Matrix3d(r.stress().total); },
          "σ, 3 × 3 [F_coh/R²]")
      .def_property_readonly(
          "sigma_plus", [](const Result& r) { return Eigen::Matrix3d(r.stress().compressive); },
          "σ⁺, the compressive part")
      .def_property_readonly(
          "sigma_minus", [](const Result& r) { return Eigen::Matrix3d(r.stress().tensile); },
          "σ⁻, the tensile part")
      .def_property_readonly("summary", &Result::summary, "summary.json's content, as a dict")
      .def_property_readonly(
          "line",
          [](const Result& r) {
            return result_line(r.scene, r.engine->world, r.engine->work.contacts, r.run);
          },
          "The command line's result line");
}

/// deposit, compact and simulate, as the commands of the same names.
void bind_runs(py::module_& m) {
  m.def(
      "deposit",
      [](const PyScene& scene) {
        SceneReadOptions how;
        how.deposition_required = true;
        return fresh_engine(scene.with({}, how));
      },
      py::arg("scene"), "The scene's ballistic deposit, as `cdpowder deposit` makes it");
  m.def(
      "load",
      [](const std::filesystem::path& path) {
        std::error_code error;
        const std::filesystem::path absolute = std::filesystem::absolute(path, error);
        return engine_from_state(load_state(path), absolute.parent_path());
      },
      py::arg("path"),
      "The World of a state file (World.save, or a run's checkpoint.cdps) with its scene, "
      "ready to step on with the same bits as the run never stopped");
  m.def(
      "compact",
      [](const PyScene& scene, const py::object& world, const py::object& callback, int every,
         const std::optional<std::filesystem::path>& out) {
        SceneReadOptions how;
        how.compaction = true;
        return start(scene.with({}, how), world, callback, every, out);
      },
      py::arg("scene"), py::arg("world") = py::none(), py::arg("callback") = py::none(),
      py::arg("every") = 1, py::arg("out") = py::none(),
      "Compaction by the piston until the blocked state, as `cdpowder compact`: on the scene's "
      "deposit, or on `world` (continued, with this scene's push). callback(world, step) runs "
      "every `every` steps; returning False stops the run. `out`: write the command line's files");
  m.def(
      "simulate",
      [](const PyScene& scene, const py::object& world, const py::object& callback, int every,
         const std::optional<std::filesystem::path>& out) {
        return start(scene, world, callback, every, out);
      },
      py::arg("scene"), py::arg("world") = py::none(), py::arg("callback") = py::none(),
      py::arg("every") = 1, py::arg("out") = py::none(),
      "The scene's run (its duration, or until blocked), as `cdpowder simulate`");
}

}  // namespace
}  // namespace cdpowder::python

// NOLINTNEXTLINE: pybind11's entry point
PYBIND11_MODULE(_core, m) {
  m.doc() = "cdpowder's engine (the package cdpowder gives its names)";
  m.attr("__version__") = cdpowder::kVersion;
  m.attr("git_commit") = cdpowder::kGitCommit;
  cdpowder::python::bind_errors(m);
  cdpowder::python::bind_scene(m);
  // Result before World, whose run() returns one: the signatures name the Python classes
  cdpowder::python::bind_result(m);
  cdpowder::python::bind_world(m);
  cdpowder::python::bind_runs(m);
}
