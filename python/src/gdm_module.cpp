// _gdm: the C++ half of the Python package `gdm` (python/gdm/__init__.py is
// the other half). numpy arrays in, plain arrays and dicts out, over the
// shared pipeline (gdm::prepare_model + gdm::run_model: the code path of the
// gdm command, the ITK filter and the MeshLab filters), so the same volume
// and options give the same mesh, bit for bit.
//
// Conventions (see the README's "Python" section):
//  - a volume is a 3D array indexed [i, j, k], i along the image's x axis
//    (ITK's index order, nibabel's get_fdata()); numpy's Fortran order is
//    then ITK's memory order (x fastest). Any real dtype and any strides;
//  - spacing (mm), origin (mm) and direction (3x3, column k = axis k: ITK's
//    GetDirection()) put voxel (i, j, k) at origin + direction @ (spacing * (i, j, k));
//  - every option of gdm::pipeline_option_catalogue() is a keyword of the
//    same name: the keywords are read from the catalogue, none is listed here.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "gdm/errors.h"
#include "gdm/mesh_checks.h"
#include "gdm/mesh_io.h"
#include "gdm/option_catalogue.h"
#include "gdm/self_contact.h"
#include "gdm/pipeline.h"
#include "gdm/shrink_wrap.h"
#if GDM_PYTHON_IMAGE_IO
#include "gdm/image_io.h"
#endif

namespace py = pybind11;

namespace {

// ---------------------------------------------------------------------------
// Exceptions: gdm.Error and its subclasses, made here so the translator and
// the Python half raise the same classes.
struct Exceptions {
  py::object error, invalid_option, invalid_volume, invalid_seed, invalid_input, model_failed, cancelled,
      wrap_too_costly;
};
Exceptions& exceptions() {
  static Exceptions* e = new Exceptions();  // never destroyed: Python owns the classes past exit
  return *e;
}

py::object new_exception(py::module_& m, const char* name, const char* doc, py::tuple bases) {
  const std::string qualified = std::string("gdm.") + name;
  PyObject* type = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases.ptr(), nullptr);
  if (!type) throw py::error_already_set();
  py::object cls = py::reinterpret_steal<py::object>(type);
  m.attr(name) = cls;
  return cls;
}

// Sets the Python error `type`(message) with attributes.
void set_error(const py::object& type, const std::string& message,
               const std::vector<std::pair<const char*, py::object>>& attributes = {}) {
  py::object instance = type(message);
  for (const auto& [key, value] : attributes) instance.attr(key) = value;
  PyErr_SetObject(type.ptr(), instance.ptr());
}

[[noreturn]] void raise(const py::object& type, const std::string& message,
                        const std::vector<std::pair<const char*, py::object>>& attributes = {}) {
  set_error(type, message, attributes);
  throw py::error_already_set();
}

[[noreturn]] void raise_type_error(const std::string& message) {
  PyErr_SetString(PyExc_TypeError, message.c_str());
  throw py::error_already_set();
}

py::dict estimate_dict(const gdm::WrapEstimate& e) {
  py::dict d;
  d["grid"] = py::make_tuple(e.grid[0], e.grid[1], e.grid[2]);
  d["cells"] = e.cells;
  d["area_mm2"] = e.area;
  d["faces"] = e.faces;
  d["cycles"] = e.cycles;
  d["seconds"] = e.seconds;
  d["bytes"] = e.bytes;
  d["text"] = e.text();
  return d;
}

void translate(std::exception_ptr p) {
  const Exceptions& x = exceptions();
  try {
    if (p) std::rethrow_exception(p);
  } catch (const gdm::WrapTooCostly& e) {
    set_error(x.wrap_too_costly, e.what(),
              {{"option", py::str(e.option())}, {"estimate", estimate_dict(e.estimate())},
               {"fitting_cell_size", py::float_(e.fitting_cell_size())}});
  } catch (const gdm::InvalidOption& e) {
    set_error(x.invalid_option, e.what(), {{"option", e.option().empty() ? py::object(py::none()) : py::str(e.option())}});
  } catch (const gdm::InvalidVolume& e) {
    set_error(x.invalid_volume, e.what());
  } catch (const gdm::InvalidSeed& e) {
    set_error(x.invalid_seed, e.what());
  } catch (const gdm::InvalidInput& e) {
    set_error(x.invalid_input, e.what());
  } catch (const gdm::ModelFailed& e) {
    set_error(x.model_failed, e.what(), {{"reason", py::str(e.what())}, {"result", py::none()}});
  } catch (const gdm::Error& e) {
    set_error(x.error, e.what());
  }
}

// ---------------------------------------------------------------------------
// Small conversions.

std::string repr_of(py::handle h) { return py::repr(h).cast<std::string>(); }

bool is_string(py::handle h) { return py::isinstance<py::str>(h); }

// A sequence of `n` finite or infinite numbers (lists, tuples, numpy arrays).
std::vector<double> numbers(py::handle h, std::size_t n, const char* what) {
  std::vector<double> out;
  if (is_string(h) || !PySequence_Check(h.ptr()) || py::len(h) != n) {
    std::ostringstream s;
    s << what << " must be " << n << " numbers, got " << repr_of(h);
    throw gdm::InvalidOption(what, s.str());
  }
  for (py::handle item : py::reinterpret_borrow<py::sequence>(h)) {
    if (py::isinstance<py::bool_>(item) || PyNumber_Check(item.ptr()) == 0 || is_string(item))
      throw gdm::InvalidOption(what, std::string(what) + " must be " + std::to_string(n) + " numbers, got " + repr_of(h));
    out.push_back(item.cast<double>());
  }
  return out;
}

gdm::Vec3 vec3(py::handle h, const char* what) {
  const auto v = numbers(h, 3, what);
  return {v[0], v[1], v[2]};
}

// 3x3, column k = the direction of axis k (ITK's GetDirection(), gdm::Volume).
Eigen::Matrix3d direction_matrix(py::handle h) {
  if (h.is_none()) return Eigen::Matrix3d::Identity();
  py::array_t<double, py::array::c_style | py::array::forcecast> a;
  try {
    a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(h);
  } catch (const py::error_already_set&) {
  }
  if (!a || a.ndim() != 2 || a.shape(0) != 3 || a.shape(1) != 3)
    throw gdm::InvalidVolume("direction must be a 3x3 matrix (column k: the direction of axis k), got " + repr_of(h));
  Eigen::Matrix3d d;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) d(r, c) = a.at(r, c);
  return d;
}

py::list list3(const gdm::Vec3& v) { return py::cast(std::vector<double>{v.x(), v.y(), v.z()}); }

py::array_t<double> matrix_array(const Eigen::Matrix3d& d) {
  py::array_t<double> out({3, 3});
  auto m = out.mutable_unchecked<2>();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m(r, c) = d(r, c);
  return out;
}

// ---------------------------------------------------------------------------
// Volumes.

// A numpy array ready to be read without the GIL: native byte order, a dtype
// the copy loop knows; the array stays referenced.
struct VolumeInput {
  py::array array;
  gdm::Index3 dims{0, 0, 0};
  std::array<py::ssize_t, 3> strides{0, 0, 0};  // bytes
  char kind = 'f';
  py::ssize_t itemsize = 4;
  std::string dtype;
};

VolumeInput volume_input(py::handle volume) {
  VolumeInput in;
  if (volume.is_none()) raise_type_error("volume must be a 3D array of real numbers, got None");
  py::module_ np = py::module_::import("numpy");
  py::array a;
  if (py::isinstance<py::array>(volume)) {
    a = py::reinterpret_borrow<py::array>(volume);
  } else {
    try {
      a = np.attr("asarray")(volume);
    } catch (const py::error_already_set& e) {
      raise_type_error(std::string("volume must be a 3D array of real numbers: ") + e.what());
    }
  }
  py::dtype dt = a.dtype();
  in.dtype = py::str(dt).cast<std::string>();
  const char kind = dt.kind();
  if (kind != 'f' && kind != 'i' && kind != 'u' && kind != 'b')
    raise_type_error("volume must hold real numbers (a float, integer or bool dtype), got dtype " + in.dtype);
  if (a.ndim() != 3) {
    std::ostringstream s;
    s << "volume must be a 3D array indexed [i, j, k] (x, y, z), got " << a.ndim() << " dimensions, shape "
      << repr_of(a.attr("shape"));
    throw gdm::InvalidVolume(s.str());
  }
  if (a.size() == 0) throw gdm::InvalidVolume("volume is empty: shape " + repr_of(a.attr("shape")));
  // Byte-swapped data and the float types the loop does not know (float16,
  // long double) go through one numpy conversion; everything else is read as is.
  const bool native = dt.attr("isnative").cast<bool>();
  const bool known = kind == 'b' || (kind == 'f' ? (dt.itemsize() == 4 || dt.itemsize() == 8)
                                                 : (dt.itemsize() == 1 || dt.itemsize() == 2 || dt.itemsize() == 4 ||
                                                    dt.itemsize() == 8));
  if (!native || !known) {
    py::object target = dt.attr("newbyteorder")("=");
    if (kind == 'f' && !known) target = py::str(dt.itemsize() < 4 ? "float32" : "float64");
    a = np.attr("asarray")(a, target);
    dt = a.dtype();
  }
  for (int d = 0; d < 3; ++d) {
    if (a.shape(d) > std::numeric_limits<int>::max())
      throw gdm::InvalidVolume("volume dimension " + std::to_string(a.shape(d)) + " is too large");
    in.dims[d] = static_cast<int>(a.shape(d));
    in.strides[d] = a.strides(d);
  }
  in.kind = dt.kind();
  in.itemsize = dt.itemsize();
  in.array = a;
  return in;
}

template <typename T>
void copy_values(const VolumeInput& in, std::vector<float>& out) {
  const auto* base = static_cast<const char*>(in.array.data());
  const std::size_t nx = static_cast<std::size_t>(in.dims[0]), ny = static_cast<std::size_t>(in.dims[1]),
                    nz = static_cast<std::size_t>(in.dims[2]);
  if (std::is_same<T, float>::value && in.strides[0] == static_cast<py::ssize_t>(sizeof(float)) &&
      in.strides[1] == static_cast<py::ssize_t>(sizeof(float) * nx) &&
      in.strides[2] == static_cast<py::ssize_t>(sizeof(float) * nx * ny)) {
    std::memcpy(out.data(), base, sizeof(float) * nx * ny * nz);  // Fortran-ordered float32: ITK's layout
    return;
  }
  float* dst = out.data();
  for (std::size_t k = 0; k < nz; ++k)
    for (std::size_t j = 0; j < ny; ++j) {
      const char* row = base + static_cast<py::ssize_t>(j) * in.strides[1] + static_cast<py::ssize_t>(k) * in.strides[2];
      for (std::size_t i = 0; i < nx; ++i) {
        T v;
        std::memcpy(&v, row + static_cast<py::ssize_t>(i) * in.strides[0], sizeof(T));
        *dst++ = static_cast<float>(v);
      }
    }
}

// The core's volume: one pass over the array into the float buffer gdm::Volume
// owns (x fastest). Runs without the GIL.
gdm::Volume make_volume(const VolumeInput& in, const gdm::Vec3& spacing, const gdm::Vec3& origin,
                        const Eigen::Matrix3d& direction) {
  std::vector<float> values(static_cast<std::size_t>(in.dims[0]) * in.dims[1] * in.dims[2]);
  switch (in.kind) {
    case 'f': in.itemsize == 4 ? copy_values<float>(in, values) : copy_values<double>(in, values); break;
    case 'b': copy_values<bool>(in, values); break;
    case 'i':
      switch (in.itemsize) {
        case 1: copy_values<std::int8_t>(in, values); break;
        case 2: copy_values<std::int16_t>(in, values); break;
        case 4: copy_values<std::int32_t>(in, values); break;
        default: copy_values<std::int64_t>(in, values); break;
      }
      break;
    default:
      switch (in.itemsize) {
        case 1: copy_values<std::uint8_t>(in, values); break;
        case 2: copy_values<std::uint16_t>(in, values); break;
        case 4: copy_values<std::uint32_t>(in, values); break;
        default: copy_values<std::uint64_t>(in, values); break;
      }
  }
  return gdm::Volume(in.dims, std::move(values), spacing, origin, direction);
}

// ---------------------------------------------------------------------------
// Options from the catalogue.

const gdm::OptionEntry<gdm::PipelineOptions>* find_option(const std::string& name) {
  for (const auto& e : gdm::pipeline_option_catalogue())
    if (e.name == name) return &e;
  return nullptr;
}

// A Python value as the catalogue's double (booleans 0/1, choices their index);
// InvalidOption naming the option otherwise.
double option_value(const gdm::OptionInfo& e, py::handle v) {
  const auto bad = [&]() -> double {
    throw gdm::InvalidOption(e.name, e.name + " must be " + gdm::range_text(e) + ", got " + repr_of(v));
    return 0.0;
  };
  switch (e.type) {
    case gdm::OptionType::boolean:
      if (py::isinstance<py::bool_>(v) || py::str(py::type::handle_of(v).attr("__name__")).cast<std::string>() == "bool_")
        return v.cast<bool>() ? 1.0 : 0.0;
      if (is_string(v)) {
        const auto s = v.cast<std::string>();
        if (s == "on") return 1.0;
        if (s == "off") return 0.0;
      }
      if (PyIndex_Check(v.ptr())) {
        const long long x = v.cast<long long>();
        if (x == 0 || x == 1) return static_cast<double>(x);
      }
      return bad();
    case gdm::OptionType::choice:
      if (is_string(v)) {
        const auto s = v.cast<std::string>();
        const auto it = std::find(e.choices.begin(), e.choices.end(), s);
        if (it != e.choices.end()) return static_cast<double>(it - e.choices.begin());
      }
      return bad();
    case gdm::OptionType::integer:
    case gdm::OptionType::real: {
      if (py::isinstance<py::bool_>(v) || is_string(v) || PyNumber_Check(v.ptr()) == 0) return bad();
      double x = 0.0;
      try {
        x = v.cast<double>();
      } catch (const py::error_already_set&) {
        return bad();
      }
      if (!gdm::accepts(e, x)) return bad();
      return x;
    }
  }
  return bad();
}

// The catalogue value as Python: bool, the choice's name, int, or float.
py::object option_python(const gdm::OptionInfo& e, double x) {
  switch (e.type) {
    case gdm::OptionType::boolean: return py::bool_(x != 0.0);
    case gdm::OptionType::choice: return py::str(gdm::value_text(e, x));
    case gdm::OptionType::integer:
      if (std::isfinite(x) && std::fabs(x) < 9e15) return py::int_(static_cast<long long>(x));
      return py::float_(x);
    default: return py::float_(x);
  }
}

// Levenshtein distance, for "did you mean".
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

[[noreturn]] void unknown_keyword(const char* function, const std::string& key,
                                  const std::vector<std::string>& extra_names) {
  std::string message = std::string(function) + "() got an unexpected keyword argument '" + key + "'";
  std::string best;
  std::size_t best_distance = 4;
  for (const auto& e : gdm::pipeline_option_catalogue()) {
    if (e.alias == key) {
      best = e.name;
      best_distance = 0;
      break;
    }
    const std::size_t d = edit_distance(key, e.name);
    if (d < best_distance) best = e.name, best_distance = d;
  }
  for (const auto& name : extra_names) {
    const std::size_t d = edit_distance(key, name);
    if (d < best_distance) best = name, best_distance = d;
  }
  if (!best.empty()) message += "; did you mean '" + best + "'?";
  message += " (gdm.options() lists every option)";
  raise_type_error(message);
}

// The seed of the Python call: "auto"/None, (x, y, z) mm, or (vertices, faces).
gdm::Mesh seed_mesh(py::handle vertices, py::handle faces) {
  py::array_t<double, py::array::c_style | py::array::forcecast> v;
  py::array_t<long long, py::array::c_style | py::array::forcecast> f;
  try {
    v = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(vertices);
    f = py::array_t<long long, py::array::c_style | py::array::forcecast>::ensure(faces);
  } catch (const py::error_already_set&) {
  }
  if (!v || v.ndim() != 2 || v.shape(1) != 3)
    throw gdm::InvalidSeed("the seed mesh's vertices must be an N x 3 array (mm), got " + repr_of(vertices));
  if (!f || f.ndim() != 2 || f.shape(1) != 3)
    throw gdm::InvalidSeed("the seed mesh's faces must be an M x 3 integer array, got " + repr_of(faces));
  gdm::Mesh mesh;
  std::vector<gdm::Mesh::VertexHandle> handles;
  auto vv = v.unchecked<2>();
  for (py::ssize_t i = 0; i < v.shape(0); ++i) {
    const gdm::Mesh::Point p(vv(i, 0), vv(i, 1), vv(i, 2));
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      throw gdm::InvalidSeed("the seed mesh's vertex " + std::to_string(i) + " is not finite");
    handles.push_back(mesh.add_vertex(p));
  }
  auto ff = f.unchecked<2>();
  const auto n = static_cast<long long>(handles.size());
  for (py::ssize_t i = 0; i < f.shape(0); ++i) {
    const long long a = ff(i, 0), b = ff(i, 1), c = ff(i, 2);
    if (a < 0 || b < 0 || c < 0 || a >= n || b >= n || c >= n)
      throw gdm::InvalidSeed("the seed mesh's face " + std::to_string(i) + " refers to a vertex outside 0.." +
                             std::to_string(n - 1));
    if (a == b || b == c || a == c)
      throw gdm::InvalidSeed("the seed mesh's face " + std::to_string(i) + " repeats a corner");
    if (!mesh.add_face(handles[a], handles[b], handles[c]).is_valid())
      throw gdm::InvalidSeed("the seed mesh's face " + std::to_string(i) +
                             " cannot join the mesh (a non-manifold edge or vertex)");
  }
  return mesh;
}

void set_seed(py::handle seed, py::handle seed_index, gdm::PipelineOptions& o) {
  const bool seed_auto = seed.is_none() || (is_string(seed) && seed.cast<std::string>() == "auto");
  if (!seed_index.is_none()) {
    if (!seed_auto) throw gdm::InvalidOption("seed", "give either seed or seed_index, not both");
    const auto v = numbers(seed_index, 3, "seed_index");
    for (int d = 0; d < 3; ++d) {
      if (v[d] != std::floor(v[d]) || std::fabs(v[d]) > 1e9)
        throw gdm::InvalidOption("seed_index", "seed_index must be 3 integer voxel indices, got " + repr_of(seed_index));
      o.seed.index[d] = static_cast<int>(v[d]);
    }
    o.seed.kind = gdm::SeedKind::index;
    return;
  }
  if (seed_auto) {
    o.seed.kind = gdm::SeedKind::automatic;
    return;
  }
  if (is_string(seed))
    throw gdm::InvalidOption("seed", "seed must be \"auto\", a point (x, y, z) in mm or a mesh (vertices, faces), got " +
                                         repr_of(seed));
  if (PySequence_Check(seed.ptr()) && py::len(seed) == 2) {
    py::sequence s = py::reinterpret_borrow<py::sequence>(seed);
    o.seed.kind = gdm::SeedKind::mesh;
    o.seed.mesh = seed_mesh(s[0], s[1]);
    return;
  }
  if (PySequence_Check(seed.ptr()) && py::len(seed) == 3) {
    o.seed.kind = gdm::SeedKind::point;
    o.seed.point = vec3(seed, "seed");
    return;
  }
  throw gdm::InvalidOption("seed", "seed must be \"auto\", a point (x, y, z) in mm or a mesh (vertices, faces), got " +
                                       repr_of(seed));
}

void set_threshold(py::handle threshold, gdm::PipelineOptions& o) {
  if (threshold.is_none() || (is_string(threshold) && threshold.cast<std::string>() == "otsu")) {
    o.threshold_otsu = true;
    return;
  }
  if (is_string(threshold) || py::isinstance<py::bool_>(threshold) || PyNumber_Check(threshold.ptr()) == 0)
    throw gdm::InvalidOption("threshold", "threshold must be a number, \"otsu\" or None, got " + repr_of(threshold));
  o.threshold_otsu = false;
  o.threshold = threshold.cast<double>();
  if (!std::isfinite(o.threshold))
    throw gdm::InvalidOption("threshold", "threshold must be a finite number, got " + repr_of(threshold));
}

void set_roi(py::handle roi, gdm::PipelineOptions& o) {
  if (roi.is_none()) return;
  const auto v = numbers(roi, 6, "roi");
  for (int d = 0; d < 6; ++d)
    if (v[d] != std::floor(v[d]) || v[d] < 0 || v[d] > 1e9)
      throw gdm::InvalidOption("roi", "roi must be 6 non-negative voxel indices (i0, j0, k0, i1, j1, k1), got " + repr_of(roi));
  for (int d = 0; d < 3; ++d) {
    o.roi.lo[d] = static_cast<int>(v[d]);
    o.roi.hi[d] = static_cast<int>(v[d + 3]);
    if (o.roi.hi[d] < o.roi.lo[d]) throw gdm::InvalidOption("roi", "roi needs i0 <= i1, j0 <= j1, k0 <= k1, got " + repr_of(roi));
  }
  o.use_roi = true;
}

// ---------------------------------------------------------------------------
// Progress and cancellation: called from the computation (without the GIL),
// takes the GIL for the callback and for Ctrl-C (PyErr_CheckSignals).
class Observer {
 public:
  explicit Observer(py::object progress) : progress_(std::move(progress)) {}
  ~Observer() {
    py::gil_scoped_acquire gil;  // the pending error's references
    pending_.reset();
  }

  bool operator()(int cycle, std::size_t faces, std::size_t moved) {
    py::gil_scoped_acquire gil;
    if (pending_) return false;
    if (PyErr_CheckSignals() != 0) {  // Ctrl-C: KeyboardInterrupt, raised once the model has stopped
      pending_.emplace();
      return false;
    }
    if (progress_.is_none()) return true;
    try {
      py::object answer = progress_(cycle, faces, moved);
      if (answer.is_none()) return true;
      const int truth = PyObject_IsTrue(answer.ptr());
      if (truth < 0) throw py::error_already_set();
      if (truth == 0) cancelled_ = true;
      return truth != 0;
    } catch (py::error_already_set& e) {
      pending_.emplace(std::move(e));
      return false;
    }
  }

  // After the computation, with the GIL: re-raises what the callback or Ctrl-C raised.
  void rethrow_pending() {
    if (pending_) {
      py::error_already_set e = std::move(*pending_);
      pending_.reset();
      throw e;
    }
  }
  bool cancelled_by_callback() const { return cancelled_; }

 private:
  py::object progress_;
  std::optional<py::error_already_set> pending_;
  bool cancelled_ = false;
};

// ---------------------------------------------------------------------------
// Results.

py::dict mesh_arrays(const gdm::Mesh& mesh, py::dict out) {
  const auto nv = static_cast<py::ssize_t>(mesh.n_vertices());
  const auto nf = static_cast<py::ssize_t>(mesh.n_faces());
  py::array_t<double> vertices({nv, py::ssize_t{3}});
  py::array_t<std::int32_t> faces({nf, py::ssize_t{3}});
  py::array_t<std::int32_t> generation(nv);
  auto v = vertices.mutable_unchecked<2>();
  auto f = faces.mutable_unchecked<2>();
  auto g = generation.mutable_unchecked<1>();
  const auto gen = gdm::find_generation_property(mesh);
  std::vector<std::int32_t> index(mesh.n_vertices(), -1);
  py::ssize_t n = 0;
  for (auto vh : mesh.vertices()) {
    const auto& p = mesh.point(vh);
    for (int d = 0; d < 3; ++d) v(n, d) = p[d];
    g(n) = gen.is_valid() ? mesh.property(gen, vh) : 0;
    index[static_cast<std::size_t>(vh.idx())] = static_cast<std::int32_t>(n);
    ++n;
  }
  py::ssize_t m = 0;
  for (auto fh : mesh.faces()) {
    int k = 0;
    for (auto vh : mesh.fv_range(fh)) {
      if (k == 3) break;
      f(m, k++) = index[static_cast<std::size_t>(vh.idx())];
    }
    ++m;
  }
  out["vertices"] = vertices;
  out["faces"] = faces;
  out["generation"] = generation;
  return out;
}

py::dict mesh_report(const gdm::Mesh& mesh, const gdm::MeshReport& r) {
  py::dict d;
  d["vertices"] = r.vertices;
  d["faces"] = r.faces;
  d["edges"] = r.edges;
  d["closed"] = r.closed;
  d["manifold"] = r.two_manifold;
  d["euler_characteristic"] = r.euler;
  d["genus"] = r.genus;
  d["components"] = r.components;
  d["euler_consistent"] = r.euler_consistent;
  d["self_intersections"] = r.self_intersections;
  d["volume_mm3"] = r.volume;
  d["volume_ml"] = r.volume / 1000.0;
  d["area_mm2"] = r.area;
  d["min_angle_deg"] = r.min_angle_deg;
  d["max_fold_deg"] = r.max_fold_deg;
  d["folds"] = r.folds;
  gdm::Vec3 lo = gdm::Vec3::Zero(), hi = gdm::Vec3::Zero();
  bool first = true;
  for (auto v : mesh.vertices()) {
    const gdm::Vec3 p = gdm::to_eigen(mesh.point(v));
    lo = first ? p : lo.cwiseMin(p);
    hi = first ? p : hi.cwiseMax(p);
    first = false;
  }
  d["bounds_min_mm"] = list3(lo);
  d["bounds_max_mm"] = list3(hi);
  int max_generation = 0;
  const auto g = gdm::find_generation_property(mesh);
  if (g.is_valid())
    for (auto v : mesh.vertices()) max_generation = std::max(max_generation, mesh.property(g, v));
  d["max_generation"] = max_generation;
  return d;
}

// Where the model meets itself (gdm/self_contact.h), as the command's JSON.
py::dict contacts_report(const gdm::ContactReport& c) {
  py::dict d;
  d["regions"] = c.regions.size();
  d["faces"] = c.faces;
  d["area_mm2"] = c.area;
  d["seam_faces"] = c.seam_faces;
  d["seam_area_mm2"] = c.seam_area;
  py::list regions;
  for (const gdm::ContactRegion& r : c.regions) {
    py::dict region;
    region["centre_mm"] = py::make_tuple(r.centre.x(), r.centre.y(), r.centre.z());
    region["area_mm2"] = r.area;
    region["faces"] = r.faces;
    region["across"] = r.across_object ? "object" : "background";
    regions.append(region);
  }
  d["list"] = regions;
  return d;
}

py::dict model_report(const gdm::DeformResult& r, double seconds, double check_seconds = 0.0) {
  py::dict d;
  d["stop_reason"] = gdm::to_string(r.reason);
  d["cycles"] = r.cycles;
  d["coarse_levels"] = r.coarse_levels;
  d["coarse_cycles"] = r.coarse_cycles;
  d["voxel_seed"] = r.voxel_seed;
  d["voxel_seed_voxels"] = r.voxel_seed_voxels;
  d["voxel_seed_background_voxels"] = r.voxel_seed_background;
  d["voxel_seed_left_out"] = r.voxel_seed_left_out;
  d["voxel_seed_surface_faces"] = r.voxel_seed_surface_faces;
  d["global_refinements"] = r.global_refinements;
  d["rejected_moves"] = r.rejected_moves;
  d["flips"] = r.flips;
  d["border_vertices"] = r.border_vertices;
  d["fit_moves"] = r.fit_moves;
  d["sharp_corners"] = r.sharp_corners;
  d["sharp_edge_moves"] = r.sharp_edge_moves;
  d["sharp_edge_splits"] = r.sharp_edge_splits;
  d["lod_splits"] = r.lod_splits;
  d["lod_collapses"] = r.lod_collapses;
  d["pleat_vertices"] = r.pleat_vertices;
  d["quality_flips"] = r.quality_flips;
  d["quality_splits"] = r.quality_splits;
  d["quality_collapses"] = r.quality_collapses;
  d["quality_moves"] = r.quality_moves;
  d["quality_spikes"] = r.quality_spikes;
  d["quality_unfolds"] = r.quality_unfolds;
  d["faces_below_min_angle"] = r.faces_below_min_angle;
  d["face_budget"] = r.face_budget;
  d["budget_faces"] = r.faces;
  d["budget_subdivisions"] = r.budget_subdivisions;
  d["budget_collapses"] = r.budget_collapses;
  d["budget_splits"] = r.budget_splits;
  d["budget_relax_moves"] = r.budget_relax_moves;
  d["float_refused"] = r.float_refused;
  d["gap_closed_voxels"] = r.gap_closed_voxels;
  d["gap_reachable_voxels"] = r.gap_reachable_voxels;
  d["bridge_vertices"] = r.bridge_vertices;
  d["channel_rounds"] = r.channel_rounds;
  d["channel_faces"] = r.channel_faces;
  d["cavities"] = r.cavities;
  d["cavity_voxels"] = r.cavity_voxels;
  d["cavity_volume_mm3"] = r.cavity_volume;
  d["cavity_specks"] = r.cavity_specks;
  d["cavities_behind_openings"] = r.cavities_behind_openings;
  d["cavity_opening_mm"] = r.cavity_opening_width;
  d["handles"] = r.handles;
  d["handle_voxels"] = r.handle_voxels;
  d["handle_repair"] = gdm::to_string(r.handle_repair);
  d["topology"] = gdm::to_string(r.topology);
  d["handles_opened"] = r.handles_opened;
  d["cavity_components"] = r.cavity_components;
  d["cavity_component_faces"] = r.cavity_component_faces;
  d["cavities_not_modelled"] = r.cavities_not_modelled;
  // Each cavity, pocket behind narrow openings and handle cap, largest first.
  py::list regions;
  for (const gdm::Cavity& c : r.filled_regions) {
    py::dict region;
    region["kind"] = gdm::to_string(c.kind);
    region["voxels"] = c.voxels;
    region["centre_mm"] = list3(c.centre);
    if (c.kind == gdm::CavityKind::narrow_openings) {
      region["openings"] = c.openings;
      region["largest_opening_mm"] = list3(c.opening_centre);
    }
    if (c.kind == gdm::CavityKind::handle) region["hole_width_mm"] = c.width;
    if (c.kind == gdm::CavityKind::cut) region["body_width_mm"] = c.width;
    regions.append(region);
  }
  d["filled_regions"] = regions;
  d["seconds"] = seconds;
  // Where the time went, wall seconds per step (gdm::StageSeconds).
  py::dict stages;
  stages["voxel_seed"] = r.seconds.voxel_seed;
  stages["gap_gate"] = r.seconds.gap_gate;
  stages["cavity_fill"] = r.seconds.cavity_fill;
  stages["growth"] = r.seconds.growth;
  stages["global_refinement"] = r.seconds.refinement;
  stages["refined_stages"] = r.seconds.refined_stages;
  stages["fit"] = r.seconds.fit;
  stages["error_lod"] = r.seconds.error_lod;
  stages["triangle_quality"] = r.seconds.quality;
  stages["float_snap"] = r.seconds.float_snap;
  stages["topology"] = r.seconds.topology;
  stages["checks"] = check_seconds;
  d["stage_seconds"] = stages;
  return d;
}

py::dict parameters(const gdm::PipelineOptions& o, py::handle seed) {
  py::dict d;
  if (o.threshold_otsu) d["threshold"] = "otsu";
  else d["threshold"] = o.threshold;
  if (o.use_roi)
    d["roi"] = py::make_tuple(o.roi.lo[0], o.roi.lo[1], o.roi.lo[2], o.roi.hi[0], o.roi.hi[1], o.roi.hi[2]);
  else d["roi"] = py::none();
  switch (o.seed.kind) {
    case gdm::SeedKind::automatic: d["seed"] = "auto"; break;
    case gdm::SeedKind::point: d["seed"] = list3(o.seed.point); break;
    case gdm::SeedKind::mesh: d["seed"] = "mesh"; break;
    case gdm::SeedKind::index: d["seed"] = py::none(); break;
  }
  (void)seed;
  if (o.seed.kind == gdm::SeedKind::index)
    d["seed_index"] = py::make_tuple(o.seed.index[0], o.seed.index[1], o.seed.index[2]);
  else d["seed_index"] = py::none();
  for (const auto& e : gdm::pipeline_option_catalogue()) d[py::str(e.name)] = option_python(e, e.get(o));
  return d;
}

// ---------------------------------------------------------------------------
// extract_surface

py::dict extract_surface(py::handle volume, py::handle spacing, py::handle origin, py::handle direction,
                         py::handle threshold, py::handle seed, py::handle seed_index, py::handle roi,
                         py::object progress, py::kwargs kwargs) {
  if (!progress.is_none() && !PyCallable_Check(progress.ptr()))
    raise_type_error("progress must be callable (cycle, faces, moving) -> bool or None, got " + repr_of(progress));
  gdm::PipelineOptions options;
  for (auto item : kwargs) {
    const std::string key = py::str(item.first).cast<std::string>();
    const auto* entry = find_option(key);
    if (!entry)
      unknown_keyword("extract_surface", key,
                      {"volume", "spacing", "origin", "direction", "threshold", "seed", "seed_index", "roi", "progress"});
    entry->set(options, option_value(*entry, item.second));
  }
  set_threshold(threshold, options);
  set_seed(seed, seed_index, options);
  set_roi(roi, options);
  const gdm::Vec3 sp = spacing.is_none() ? gdm::Vec3(gdm::Vec3::Ones()) : vec3(spacing, "spacing");
  const gdm::Vec3 org = origin.is_none() ? gdm::Vec3(gdm::Vec3::Zero()) : vec3(origin, "origin");
  const Eigen::Matrix3d dir = direction_matrix(direction);
  gdm::validate(options);  // every option before the volume is read
  const VolumeInput input = volume_input(volume);

  Observer observer(progress);
  gdm::PipelineResult result;
  gdm::Vec3 value_range;
  {
    py::gil_scoped_release release;
    const gdm::Volume v = make_volume(input, sp, org, dir);
    value_range = gdm::Vec3(v.min_value(), v.max_value(), 0.0);
    const gdm::PreparedModel prepared = gdm::prepare_model(v, options);
    result = gdm::run_model(prepared, [&](const gdm::PipelineProgress& p) {
      return observer(p.cycle.cycle, p.cycle.faces, p.cycle.moved);
    });
  }
  observer.rethrow_pending();

  py::dict out;
  mesh_arrays(result.mesh, out);
  py::dict report;
  report["status"] = result.failure.empty() ? std::string("ok") : result.failure;
  py::dict input_report;
  input_report["size"] = py::make_tuple(input.dims[0], input.dims[1], input.dims[2]);
  input_report["dtype"] = input.dtype;
  input_report["spacing_mm"] = list3(sp);
  input_report["origin_mm"] = list3(org);
  std::vector<double> d9;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) d9.push_back(dir(r, c));
  input_report["direction"] = d9;
  input_report["value_min"] = value_range.x();
  input_report["value_max"] = value_range.y();
  report["input"] = input_report;
  const gdm::PipelineChoices& c = result.choices;
  py::dict t;
  t["value"] = c.threshold;
  t["source"] = c.threshold_source;
  report["threshold"] = t;
  py::dict s;
  s["source"] = c.seed_source;
  s["center_mm"] = list3(c.seed_center);
  s["radius_mm"] = c.seed_radius;
  if (c.seed_source == "auto") {
    s["depth_mm"] = c.auto_seed.depth;
    s["region_voxels"] = c.auto_seed.region_voxels;
    s["regions"] = c.auto_seed.regions;
  }
  s["cut_by_scan"] = c.cut_by_scan;
  s["border_fraction"] = c.border.fraction();
  s["border_sides"] = c.border.sides_text();
  report["seed"] = s;
  report["model"] = model_report(result.deform, result.seconds, result.check_seconds);
  report["mesh"] = mesh_report(result.mesh, result.report);
  py::dict contacts = contacts_report(result.contacts);
  // Seams a start from the object's voxels would not leave (voxel_seed=True).
  contacts["seams_worth_a_voxel_seed"] = gdm::voxel_seed_applies(options.deform) && !result.deform.voxel_seed &&
                                         gdm::seams_worth_a_voxel_seed(result.contacts, result.report.area);
  report["contacts"] = contacts;
  report["parameters"] = parameters(options, seed);
  out["report"] = report;
  out["failure"] = result.failure;
  out["cancelled"] = observer.cancelled_by_callback();
  return out;
}

// ---------------------------------------------------------------------------
// wrap

// A mesh given as arrays: vertices N x 3 (mm) and faces M x 3 (indices),
// C-ordered doubles and 64-bit integers; InvalidOption naming the bad one.
struct MeshArrays {
  py::array_t<double, py::array::c_style | py::array::forcecast> v;
  py::array_t<long long, py::array::c_style | py::array::forcecast> f;
};

MeshArrays mesh_arrays_of(py::handle vertices, py::handle faces) {
  MeshArrays m;
  try {
    m.v = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(vertices);
    m.f = py::array_t<long long, py::array::c_style | py::array::forcecast>::ensure(faces);
  } catch (const py::error_already_set&) {
  }
  if (!m.v || m.v.ndim() != 2 || m.v.shape(1) != 3)
    throw gdm::InvalidOption("vertices", "vertices must be an N x 3 array (mm), got " + repr_of(vertices));
  if (!m.f || m.f.ndim() != 2 || m.f.shape(1) != 3)
    throw gdm::InvalidOption("faces", "faces must be an M x 3 integer array, got " + repr_of(faces));
  return m;
}

std::vector<gdm::Triangle> triangles(py::handle vertices, py::handle faces) {
  const MeshArrays arrays = mesh_arrays_of(vertices, faces);
  const auto& v = arrays.v;
  const auto& f = arrays.f;
  auto vv = v.unchecked<2>();
  auto ff = f.unchecked<2>();
  std::vector<gdm::Triangle> out;
  out.reserve(static_cast<std::size_t>(f.shape(0)));
  for (py::ssize_t i = 0; i < f.shape(0); ++i) {
    gdm::Triangle t;
    for (int k = 0; k < 3; ++k) {
      const long long idx = ff(i, k);
      if (idx < 0 || idx >= v.shape(0))
        throw gdm::InvalidOption("faces", "face " + std::to_string(i) + " refers to vertex " + std::to_string(idx) +
                                              " of " + std::to_string(v.shape(0)));
      t[k] = gdm::Vec3(vv(idx, 0), vv(idx, 1), vv(idx, 2));
    }
    out.push_back(t);
  }
  return out;
}

gdm::WrapOptions wrap_options(double tolerance, py::handle cell_size, int coverage_rounds, double a0, double a1,
                              double a2, double lod_face_area, int global_refinements, int max_cycles, int threads,
                              double time_limit, double memory_limit, double bridge) {
  gdm::WrapOptions o;
  if (!(tolerance > 0.0) || !std::isfinite(tolerance))
    throw gdm::InvalidOption("tolerance", "tolerance must be > 0 (mm), got " + std::to_string(tolerance));
  o.tolerance = tolerance;
  o.cell_size = cell_size.is_none() ? tolerance / 3.0 : cell_size.cast<double>();
  if (!(o.cell_size > 0.0) || o.cell_size > tolerance)
    throw gdm::InvalidOption("cell_size", "cell_size must be in (0, tolerance], got " + repr_of(cell_size));
  if (coverage_rounds < 0) throw gdm::InvalidOption("coverage_rounds", "coverage_rounds must be >= 0");
  o.coverage_rounds = coverage_rounds;
  o.a0 = a0;
  o.a1 = a1;
  o.a2 = a2;
  o.lod_face_area = lod_face_area;
  o.global_refinements = global_refinements;
  o.max_cycles = max_cycles;
  o.threads = threads;
  o.time_limit = time_limit;
  o.memory_limit = memory_limit;
  o.bridge = bridge;
  return o;
}

py::dict estimate_wrap(py::handle vertices, py::handle faces, double tolerance, py::handle cell_size,
                       int coverage_rounds, double a0, double a1, double a2, double lod_face_area,
                       int global_refinements, int max_cycles, int threads, double time_limit, double memory_limit,
                       double bridge) {
  const gdm::WrapOptions o = wrap_options(tolerance, cell_size, coverage_rounds, a0, a1, a2, lod_face_area,
                                          global_refinements, max_cycles, threads, time_limit, memory_limit, bridge);
  const std::vector<gdm::Triangle> input = triangles(vertices, faces);
  gdm::WrapEstimate e;
  {
    py::gil_scoped_release release;
    e = gdm::estimate_wrap(input, o);
  }
  return estimate_dict(e);
}

py::dict wrap(py::handle vertices, py::handle faces, double tolerance, py::handle cell_size, int coverage_rounds,
              double a0, double a1, double a2, double lod_face_area, int global_refinements, int max_cycles,
              int threads, double time_limit, double memory_limit, double bridge, py::object progress) {
  if (!progress.is_none() && !PyCallable_Check(progress.ptr()))
    raise_type_error("progress must be callable (cycle, faces, moving) -> bool or None, got " + repr_of(progress));
  const gdm::WrapOptions o = wrap_options(tolerance, cell_size, coverage_rounds, a0, a1, a2, lod_face_area,
                                          global_refinements, max_cycles, threads, time_limit, memory_limit, bridge);
  const std::vector<gdm::Triangle> input = triangles(vertices, faces);
  Observer observer(progress);
  gdm::WrapResult r;
  try {
    py::gil_scoped_release release;
    r = gdm::shrink_wrap(input, o, [&](const gdm::CycleReport& c) { return observer(c.cycle, c.faces, c.moved); });
  } catch (const gdm::InvalidOption&) {
    throw;  // WrapTooCostly among them: refused before any work
  } catch (const gdm::Error& e) {
    observer.rethrow_pending();
    if (observer.cancelled_by_callback()) raise(exceptions().cancelled, "cancelled by the progress callback");
    raise(exceptions().model_failed, std::string("the wrap failed: ") + e.what(),
          {{"reason", py::str(e.what())}, {"result", py::none()}});
  }
  observer.rethrow_pending();
  py::dict out;
  mesh_arrays(r.mesh, out);
  py::dict report;
  report["status"] = "ok";
  report["input_triangles"] = input.size();
  report["mesh"] = mesh_report(r.mesh, r.report);
  report["model"] = model_report(r.deform, 0.0);
  report["model"]["cycles"] = r.total_cycles;
  report["coverage_rounds_done"] = r.coverage_rounds_done;
  report["farthest_input_distance_mm"] = r.farthest_input_distance;
  report["farthest_wrap_distance_mm"] = r.farthest_wrap_distance;
  report["notes"] = r.notes;
  py::dict p;
  p["tolerance"] = o.tolerance;
  p["cell_size"] = o.cell_size;
  p["coverage_rounds"] = o.coverage_rounds;
  p["a0"] = o.a0;
  p["a1"] = o.a1;
  p["a2"] = o.a2;
  p["lod_face_area"] = o.lod_face_area;
  p["global_refinements"] = o.global_refinements;
  p["max_cycles"] = o.max_cycles;
  p["threads"] = o.threads;
  report["parameters"] = p;
  out["report"] = report;
  out["failure"] = std::string();
  out["cancelled"] = false;
  return out;
}

// ---------------------------------------------------------------------------
// Files.

void write_mesh(const std::string& path, py::handle vertices, py::handle faces, py::handle generation) {
  gdm::MeshFileData data;
  const MeshArrays arrays = mesh_arrays_of(vertices, faces);
  const auto& v = arrays.v;
  const auto& f = arrays.f;
  auto vv = v.unchecked<2>();
  auto ff = f.unchecked<2>();
  for (py::ssize_t i = 0; i < v.shape(0); ++i) {
    const gdm::Vec3 p(vv(i, 0), vv(i, 1), vv(i, 2));
    if (!p.allFinite()) throw gdm::InvalidOption("vertices", "vertex " + std::to_string(i) + " is not finite");
    data.points.push_back(p);
  }
  for (py::ssize_t i = 0; i < f.shape(0); ++i) {
    std::array<std::uint32_t, 3> t{};
    for (int k = 0; k < 3; ++k) {
      if (ff(i, k) < 0 || ff(i, k) >= v.shape(0))
        throw gdm::InvalidOption("faces", "face " + std::to_string(i) + " refers to vertex " + std::to_string(ff(i, k)) +
                                              " of " + std::to_string(v.shape(0)));
      t[k] = static_cast<std::uint32_t>(ff(i, k));
    }
    data.triangles.push_back(t);
  }
  if (!generation.is_none()) {
    auto g = py::array_t<int, py::array::c_style | py::array::forcecast>::ensure(generation);
    if (!g || g.ndim() != 1 || g.shape(0) != v.shape(0))
      throw gdm::InvalidOption("generation", "generation must hold one integer per vertex");
    data.generation.assign(g.data(), g.data() + g.shape(0));
  }
  try {
    py::gil_scoped_release release;
    gdm::write_mesh(data, path);
  } catch (const gdm::InvalidOption&) {
    throw;
  } catch (const gdm::Error& e) {
    PyErr_SetString(PyExc_OSError, e.what());
    throw py::error_already_set();
  }
}

py::dict read_mesh(const std::string& path) {
  gdm::MeshFileData data;
  {
    py::gil_scoped_release release;
    data = gdm::read_mesh_file(path);
  }
  const auto nv = static_cast<py::ssize_t>(data.points.size());
  const auto nf = static_cast<py::ssize_t>(data.triangles.size());
  py::array_t<double> vertices({nv, py::ssize_t{3}});
  py::array_t<std::int32_t> faces({nf, py::ssize_t{3}});
  auto v = vertices.mutable_unchecked<2>();
  auto f = faces.mutable_unchecked<2>();
  for (py::ssize_t i = 0; i < nv; ++i)
    for (int d = 0; d < 3; ++d) v(i, d) = data.points[static_cast<std::size_t>(i)][d];
  for (py::ssize_t i = 0; i < nf; ++i)
    for (int d = 0; d < 3; ++d) f(i, d) = static_cast<std::int32_t>(data.triangles[static_cast<std::size_t>(i)][d]);
  py::dict out;
  out["vertices"] = vertices;
  out["faces"] = faces;
  if (data.generation.empty()) out["generation"] = py::none();
  else out["generation"] = py::array_t<std::int32_t>(nv, data.generation.data());
  return out;
}

#if GDM_PYTHON_IMAGE_IO
// The volume's own buffer becomes the array (no copy): a capsule owns the
// gdm::Volume, the array views its values in Fortran order [i, j, k].
py::tuple read_image(const std::string& path, py::handle series) {
  gdm::ReadOptions options;
  if (!series.is_none()) options.series_uid = series.cast<std::string>();
  gdm::ImageInfo info;
  auto volume = std::make_unique<gdm::Volume>();
  {
    py::gil_scoped_release release;
    *volume = gdm::read_volume(path, options, &info);
  }
  const gdm::Volume& v = *volume;
  const gdm::Vec3 spacing = v.spacing(), origin = v.origin();
  const Eigen::Matrix3d direction = v.direction();
  const auto nx = static_cast<py::ssize_t>(v.dims()[0]), ny = static_cast<py::ssize_t>(v.dims()[1]),
             nz = static_cast<py::ssize_t>(v.dims()[2]);
  auto* data = const_cast<float*>(v.values().data());
  py::capsule owner(volume.release(), [](void* p) { delete static_cast<gdm::Volume*>(p); });
  const auto f = static_cast<py::ssize_t>(sizeof(float));
  py::array_t<float> array({nx, ny, nz}, {f, f * nx, f * nx * ny}, data, owner);
  py::dict information;
  information["format"] = info.format;
  information["pixel_type"] = info.pixel_type;
  information["series_uid"] = info.series_uid;
  information["series_count"] = info.series_count;
  information["slices"] = info.slices;
  information["warnings"] = info.warnings;
  return py::make_tuple(array, py::make_tuple(spacing.x(), spacing.y(), spacing.z()),
                        py::make_tuple(origin.x(), origin.y(), origin.z()), matrix_array(direction), information);
}
#endif

// The catalogue as Python: one dict per option.
py::list option_catalogue() {
  py::list out;
  const gdm::PipelineOptions defaults;
  for (const auto& e : gdm::pipeline_option_catalogue()) {
    py::dict d;
    d["name"] = e.name;
    d["group"] = e.group;
    d["unit"] = e.unit;
    d["help"] = e.help;
    const char* type = "real";
    switch (e.type) {
      case gdm::OptionType::integer: type = "integer"; break;
      case gdm::OptionType::boolean: type = "boolean"; break;
      case gdm::OptionType::choice: type = "choice"; break;
      default: break;
    }
    d["type"] = type;
    d["default"] = option_python(e, e.get(defaults));
    d["range"] = gdm::range_text(e);
    d["choices"] = e.choices;
    d["alias"] = e.alias;
    out.append(d);
  }
  return out;
}

}  // namespace

PYBIND11_MODULE(_gdm, m) {
  m.doc() = "gdm's C++ half (use the package gdm)";
  Exceptions& x = exceptions();
  x.error = new_exception(m, "Error", "Base of every gdm error.", py::make_tuple(py::handle(PyExc_Exception)));
  x.invalid_option = new_exception(m, "InvalidOption",
                                   "An option, keyword or argument out of its range; .option names it.",
                                   py::make_tuple(x.error, py::handle(PyExc_ValueError)));
  x.invalid_volume = new_exception(m, "InvalidVolume",
                                   "A volume gdm cannot use: not 3D, empty, NaN values, zero spacing, constant, ...",
                                   py::make_tuple(x.error, py::handle(PyExc_ValueError)));
  x.invalid_seed = new_exception(m, "InvalidSeed", "A seed outside the volume or the object, or an unusable seed mesh.",
                                 py::make_tuple(x.error, py::handle(PyExc_ValueError)));
  x.invalid_input = new_exception(m, "InvalidInput",
                                  "A file that cannot be read or contradicts itself (missing, truncated, corrupt).",
                                  py::make_tuple(x.error, py::handle(PyExc_OSError)));
  x.model_failed = new_exception(m, "ModelFailed",
                                 "The model ran but its result is not the object (a leak to the border, the face "
                                 "limit, the time limit); .reason says why, .result holds the mesh.",
                                 py::make_tuple(x.error, py::handle(PyExc_RuntimeError)));
  x.wrap_too_costly = new_exception(
      m, "WrapTooCostly",
      "A wrap refused before it starts: its estimate exceeds time_limit or memory_limit. .estimate holds the "
      "estimate (seconds, bytes, grid, faces), .fitting_cell_size the smallest cell size within the limits.",
      py::make_tuple(x.invalid_option));
  x.cancelled = new_exception(m, "Cancelled", "The progress callback returned False; .result holds the mesh so far.",
                              py::make_tuple(x.error));
  py::register_exception_translator(&translate);

  m.def("extract_surface", &extract_surface, py::arg("volume"), py::arg("spacing"), py::arg("origin"),
        py::arg("direction"), py::arg("threshold"), py::arg("seed"), py::arg("seed_index"), py::arg("roi"),
        py::arg("progress"));
  m.def("wrap", &wrap, py::arg("vertices"), py::arg("faces"), py::arg("tolerance"), py::arg("cell_size"),
        py::arg("coverage_rounds"), py::arg("a0"), py::arg("a1"), py::arg("a2"), py::arg("lod_face_area"),
        py::arg("global_refinements"), py::arg("max_cycles"), py::arg("threads"), py::arg("time_limit"),
        py::arg("memory_limit"), py::arg("bridge"), py::arg("progress"));
  m.def("estimate_wrap", &estimate_wrap, py::arg("vertices"), py::arg("faces"), py::arg("tolerance"),
        py::arg("cell_size"), py::arg("coverage_rounds"), py::arg("a0"), py::arg("a1"), py::arg("a2"),
        py::arg("lod_face_area"), py::arg("global_refinements"), py::arg("max_cycles"), py::arg("threads"),
        py::arg("time_limit"), py::arg("memory_limit"), py::arg("bridge"));
  m.def("write_mesh", &write_mesh, py::arg("path"), py::arg("vertices"), py::arg("faces"), py::arg("generation"));
  m.def("read_mesh", &read_mesh, py::arg("path"));
  m.def("option_catalogue", &option_catalogue);
  m.def("options_markdown", &gdm::options_markdown);
#if GDM_PYTHON_IMAGE_IO
  m.def("read_image", &read_image, py::arg("path"), py::arg("series"));
  m.attr("has_image_io") = true;
#else
  m.attr("has_image_io") = false;
#endif
  m.attr("__version__") = GDM_VERSION;
}
