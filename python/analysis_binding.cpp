// aggkit.analysis on the caller's own arrays: positions (N×2 or N×3) of equal spheres of radius R, with an
// optional box (sides; periodic or not) — configurations from any code.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <variant>

#include "analysis/clusters.hpp"
#include "analysis/fractal_dimension.hpp"
#include "analysis/input_error.hpp"
#include "analysis/shape.hpp"

namespace py = pybind11;
using namespace aggkit;

namespace {

using Points = py::array_t<double, py::array::c_style | py::array::forcecast>;

std::vector<std::array<double, 3>> points_of(const Points& p, int* dimension) {
  if (p.ndim() != 2 || (p.shape(1) != 2 && p.shape(1) != 3))
    throw InputError("positions", "an array of shape (" + std::to_string(p.ndim() >= 1 ? p.shape(0) : 0) + ", ...)",
                     "an N×2 or N×3 array");
  *dimension = int(p.shape(1));
  std::vector<std::array<double, 3>> points(std::size_t(p.shape(0)), {0, 0, 0});
  const auto a = p.unchecked<2>();
  for (py::ssize_t i = 0; i < p.shape(0); ++i)
    for (int d = 0; d < *dimension; ++d) points[std::size_t(i)][std::size_t(d)] = a(i, d);
  return points;
}

// One radius for every particle, or one per particle (their mean is the reference radius of the ranges).
using Radius = std::variant<double, std::vector<double>>;

ParticleConfiguration configuration_of(const Points& positions, const Radius& radius, const std::optional<std::vector<double>>& box,
                                       bool periodic) {
  ParticleConfiguration c;
  c.positions = points_of(positions, &c.dimension);
  if (const double* r = std::get_if<double>(&radius)) {
    c.radius = *r;
  } else {
    c.radii = std::get<std::vector<double>>(radius);
    if (c.radii.empty()) throw InputError("radius", "[]", "a radius, or one per particle");
    double sum = 0;
    for (double r : c.radii) sum += r;
    c.radius = sum / double(c.radii.size());
  }
  c.periodic = periodic;
  if (box) {
    if (int(box->size()) != c.dimension) throw InputError("box", std::to_string(box->size()) + " sides", "one side per dimension");
    for (int d = 0; d < c.dimension; ++d) c.box[std::size_t(d)] = (*box)[std::size_t(d)];
  } else if (periodic) {
    throw InputError("periodic", "true", "a box (its sides) for periodic distances");
  }
  check_configuration(c);
  return c;
}

py::dict fit_dict(const FractalFit& f) {
  py::dict d;
  d["dimension"] = f.dimension, d["standard_error"] = f.standard_error, d["fit_min"] = f.fit_min,
  d["fit_max"] = f.fit_max, d["rule"] = f.rule;
  d["scale"] = f.scale, d["count"] = f.count;
  return d;
}

}  // namespace

void bind_analysis(py::module_& m) {
  using Box = std::optional<std::vector<double>>;
  m.def("contact_clusters",
        [](const Points& x, const Radius& radius, Box box, bool periodic, double contact_distance) {
          const ParticleConfiguration c = configuration_of(x, radius, box, periodic);
          return contact_clusters(c, contact_distance > 0 ? contact_distance : 2 * c.radius * (1 + 1e-9));
        },
        py::arg("positions"), py::arg("radius"), py::arg("box") = py::none(), py::arg("periodic") = false,
        py::arg("contact_distance") = 0.0);
  m.def("relative_contacts",
        [](const Points& x, const Radius& radius, Box box, bool periodic, double factor, bool with_self) {
          return relative_contacts(configuration_of(x, radius, box, periodic), factor,
                                   with_self ? ContactCounting::with_self : ContactCounting::other_particles);
        },
        py::arg("positions"), py::arg("radius"), py::arg("box") = py::none(), py::arg("periodic") = false,
        py::arg("factor") = 2.1, py::arg("with_self") = false);
  m.def("pair_distribution",
        [](const Points& x, const Radius& radius, Box box, bool periodic, std::optional<std::vector<double>> r) {
          const ParticleConfiguration c = configuration_of(x, radius, box, periodic);
          const PairDistribution p = pair_distribution(c, r ? *r : pair_distribution_radii(c.radius, 90));
          return py::make_tuple(p.r, p.p);
        },
        py::arg("positions"), py::arg("radius"), py::arg("box") = py::none(), py::arg("periodic") = false,
        py::arg("r") = py::none());
  m.def("gyration", [](const Points& x) {
    int dimension = 0;
    const auto points = points_of(x, &dimension);
    const Gyration g = gyration(points, dimension);
    py::dict d;
    d["eigenvalues"] = g.eigenvalues, d["aspect_ratio"] = g.aspect_ratio, d["principal_axis"] = g.principal_axis;
    d["orientation"] = g.orientation, d["radius_of_gyration"] = g.radius_of_gyration;
    return d;
  }, py::arg("points"));
  m.def("box_counting_dimension", [](const Points& x, double radius, double box_side) {
    int dimension = 0;
    const auto p = points_of(x, &dimension);
    return fit_dict(box_counting_dimension(p, dimension, radius, box_side));
  }, py::arg("points"), py::arg("radius"), py::arg("box_side") = 0.0);
  m.def("mass_radius_dimension", [](const Points& x, double radius) {
    int dimension = 0;
    const auto p = points_of(x, &dimension);
    return fit_dict(mass_radius_dimension(p, dimension, radius));
  }, py::arg("points"), py::arg("radius"));
}
