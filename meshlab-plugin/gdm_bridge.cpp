#include "gdm_bridge.h"

#include <array>
#include <memory>

#include "gdm/errors.h"
#include "gdm/mesh_checks.h"
#include "gdm/seed.h"
#include "volume_io.h"

namespace gdm_meshlab {
gdm::Mesh to_gdm_seed(const CMeshO& m, LogLines* log) {
  gdm::Mesh mesh;
  std::vector<gdm::Mesh::VertexHandle> handle(m.vert.size());
  std::vector<std::array<gdm::Mesh::VertexHandle, 3>> faces;
  for (const CFaceO& f : m.face) {
    if (f.IsD()) continue;
    std::array<gdm::Mesh::VertexHandle, 3> tri;
    for (int i = 0; i < 3; ++i) {
      const std::size_t idx = vcg::tri::Index(m, f.cV(i));
      if (!handle[idx].is_valid()) {
        const auto& p = f.cV(i)->cP();
        handle[idx] = mesh.add_vertex(gdm::Mesh::Point(p[0], p[1], p[2]));
      }
      tri[i] = handle[idx];
    }
    faces.push_back(tri);
  }
  if (faces.empty()) throw gdm::InvalidSeed("the current layer has no faces: a closed triangle mesh is needed");
  for (std::size_t i = 0; i < faces.size(); ++i) {
    const auto& t = faces[i];
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
      throw gdm::InvalidSeed("the current layer is not a 2-manifold: face " + std::to_string(i) +
                             " uses the same vertex twice (try Filters > Cleaning and Repairing)");
    if (!mesh.add_face(t[0], t[1], t[2]).is_valid())
      throw gdm::InvalidSeed("the current layer is not a 2-manifold: face " + std::to_string(i) +
                             " meets an edge already shared by two faces, or is oriented against its "
                             "neighbours (try Filters > Cleaning and Repairing)");
  }
  gdm::check_seed_mesh(mesh);  // closed, 2-manifold, finite
  if (gdm::enclosed_volume(mesh) < 0.0) {
    gdm::Mesh flipped;
    for (auto v : mesh.vertices()) flipped.add_vertex(mesh.point(v));
    for (const auto& t : faces) flipped.add_face(t[0], t[2], t[1]);
    mesh = std::move(flipped);
    if (log) log->push_back("the layer's faces pointed inwards; they were reversed");
  }
  return mesh;
}

void to_meshlab(const gdm::Mesh& mesh, CMeshO& out) {
  out.Clear();
  const auto generation = gdm::find_generation_property(mesh);
  std::vector<int> index(mesh.n_vertices(), -1);
  std::size_t nv = 0, nf = 0;
  for (auto v : mesh.vertices()) index[v.idx()] = static_cast<int>(nv++);
  for (auto f : mesh.faces()) { (void)f; ++nf; }
  auto vi = vcg::tri::Allocator<CMeshO>::AddVertices(out, nv);
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    CVertexO& cv = out.vert[index[v.idx()]];
    cv.P() = Point3m(static_cast<Scalarm>(p[0]), static_cast<Scalarm>(p[1]), static_cast<Scalarm>(p[2]));
    cv.Q() = generation.is_valid() ? static_cast<float>(mesh.property(generation, v)) : 0.0f;
  }
  (void)vi;
  auto fi = vcg::tri::Allocator<CMeshO>::AddFaces(out, nf);
  for (auto f : mesh.faces()) {
    int k = 0;
    for (auto v : mesh.fv_range(f)) fi->V(k++) = &out.vert[index[v.idx()]];
    ++fi;
  }
}

std::vector<gdm::Triangle> triangle_soup(const CMeshO& m) {
  std::vector<gdm::Triangle> soup;
  const auto point = [](const CVertexO* v) {
    return gdm::Vec3(v->cP()[0], v->cP()[1], v->cP()[2]);
  };
  for (const CFaceO& f : m.face)
    if (!f.IsD()) soup.push_back({point(f.cV(0)), point(f.cV(1)), point(f.cV(2))});
  if (soup.empty())
    for (const CVertexO& v : m.vert)
      if (!v.IsD()) soup.push_back({point(&v), point(&v), point(&v)});
  for (const auto& t : soup)
    for (const auto& p : t)
      if (!p.allFinite()) throw gdm::InvalidOption("the current layer has vertices with non-finite coordinates");
  return soup;
}

gdm::Mesh model_from_volume(const std::string& volume_file, const gdm::PipelineOptions& options,
                            const Progress& progress, LogLines* log) {
  if (progress) progress(0, "Reading the volume");
  std::string description;
  const gdm::Volume volume = read_volume(volume_file, &description);
  log->push_back(description);
  if (progress) progress(3, "Threshold and seed");
  const gdm::PreparedModel prepared = gdm::prepare_model(volume, options);
  for (const auto& line : gdm::describe_choices(prepared)) log->push_back(line);
  const gdm::PipelineResult r = gdm::run_model(prepared, [&](const gdm::PipelineProgress& p) {
    return !progress || progress(5 + static_cast<int>(94.0 * p.fraction), "Deforming the model");
  });
  if (r.deform.reason == gdm::StopReason::cancelled) throw gdm::Error("cancelled");
  log_result(r, gdm::voxel_seed_applies(prepared.deform), log);
  gdm::require_success(r);
  return r.mesh;
}

gdm::Mesh shrink_wrap(const std::vector<gdm::Triangle>& soup, gdm::WrapOptions w, const Progress& progress,
                      LogLines* log) {
  if (soup.empty()) throw gdm::InvalidOption("the current layer is empty: nothing to wrap");
  gdm::DeformObserver observer;
  if (progress) {
    w.field_progress = [progress](double f) {
      return progress(static_cast<int>(20 * f), "Distance field of the input");
    };
    const int refinements = w.global_refinements;
    auto estimator = std::make_shared<gdm::ProgressEstimator>(refinements, w.max_cycles);
    observer = [progress, estimator, refinements](const gdm::CycleReport& r) {
      if (r.stage <= refinements) return progress(20 + static_cast<int>(70 * estimator->update(r)), "Shrinking the wrap");
      return progress(90 + (r.stage - refinements), "Covering the input");  // coverage round r.stage - refinements
    };
  }
  log->push_back("estimate: " + gdm::estimate_wrap(soup, w).text());
  gdm::WrapResult r = gdm::shrink_wrap(soup, w, observer);
  log->insert(log->end(), r.notes.begin(), r.notes.end());
  return std::move(r.mesh);
}

}  // namespace gdm_meshlab
