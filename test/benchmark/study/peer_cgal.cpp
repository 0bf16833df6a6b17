// CGAL Mesh_3 peer of the benchmark study (see peer_cgal.h). No gdm, VTK or ITK header here.
#include "peer_cgal.h"

#include <chrono>
#include <cstring>
#include <iostream>
#include <map>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Image_3.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/Mesh_3/initialize_triangulation_from_gray_image.h>
#include <CGAL/make_mesh_3.h>

namespace study {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Domain = CGAL::Labeled_mesh_domain_3<K>;
using Tr = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
using C3t3 = CGAL::Mesh_complex_3_in_triangulation_3<Tr>;
using Criteria = CGAL::Mesh_criteria_3<Tr>;

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace

PeerResult run_cgal_mesh3(const Image& image, double threshold, bool object_brighter, double facet_distance) {
  // CGAL's gray-level domain puts the object where the value exceeds the iso
  // value: a darker object is meshed on the negated image.
  _image* raw = _createImage(image.dims[0], image.dims[1], image.dims[2], 1, image.spacing[0], image.spacing[1],
                             image.spacing[2], sizeof(float), WK_FLOAT, SGN_SIGNED);
  float* data = static_cast<float*>(raw->data);
  float lowest = image.values.empty() ? 0.0f : image.values[0];
  for (std::size_t i = 0; i < image.values.size(); ++i) {
    data[i] = object_brighter ? image.values[i] : -image.values[i];
    lowest = std::min(lowest, data[i]);
  }
  raw->tx = static_cast<float>(image.origin[0]);
  raw->ty = static_cast<float>(image.origin[1]);
  raw->tz = static_cast<float>(image.origin[2]);
  CGAL::Image_3 cgal_image(raw);
  const double iso = object_brighter ? threshold : -threshold;

  const auto t0 = Clock::now();
  namespace params = CGAL::parameters;
  Domain domain = Domain::create_gray_image_mesh_domain(cgal_image, params::iso_value = iso,
                                                        params::value_outside = lowest);
  // Surface criteria only: the tetrahedra inside are not refined (only the boundary is wanted).
  Criteria criteria(params::facet_angle = 25.0, params::facet_distance = facet_distance);
  C3t3 c3t3;
  // CGAL's image initialisation reports its progress on std::cout: silence it.
  struct Mute {
    std::streambuf* saved = std::cout.rdbuf(nullptr);
    ~Mute() { std::cout.rdbuf(saved); }
  } mute;
  initialize_triangulation_from_gray_image(c3t3, domain, cgal_image, criteria, static_cast<float>(iso), float());
  CGAL::refine_mesh_3(c3t3, domain, criteria, params::no_perturb(), params::no_exude());
  PeerResult r;
  // The boundary surface: facets of the complex, oriented away from the object's cells.
  std::map<Tr::Vertex_handle, int> ids;
  auto id_of = [&](Tr::Vertex_handle v) {
    auto [it, inserted] = ids.emplace(v, static_cast<int>(r.surface.points.size()));
    if (inserted) {
      const auto& p = c3t3.triangulation().point(v);
      r.surface.points.push_back({CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())});
    }
    return it->second;
  };
  for (auto f = c3t3.facets_in_complex_begin(); f != c3t3.facets_in_complex_end(); ++f) {
    Tr::Cell_handle c = f->first;
    int i = f->second;
    if (!c3t3.is_in_complex(c)) {  // look from the inside cell
      const Tr::Cell_handle n = c->neighbor(i);
      i = n->index(c);
      c = n;
    }
    // CGAL's vertex_triple_index lists facet i counterclockwise seen from
    // vertex i (inside the cell); reversed, the facet faces away from the object.
    const int a = Tr::vertex_triple_index(i, 0), b = Tr::vertex_triple_index(i, 1), d = Tr::vertex_triple_index(i, 2);
    r.surface.faces.push_back({id_of(c->vertex(a)), id_of(c->vertex(d)), id_of(c->vertex(b))});
  }
  r.seconds = seconds_since(t0);
  char note[64];
  std::snprintf(note, sizeof(note), "facet_distance %.3g mm", facet_distance);
  r.note = note;
  return r;
}

}  // namespace study
