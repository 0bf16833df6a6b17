// Seed models (paper section 4): the closed polyhedron the deformation starts from.
#pragma once

#include "gdm/mesh.h"

namespace gdm {

// The 20-face icosahedron inscribed in the sphere (center, radius).
Mesh make_icosahedron(const Vec3& center, double radius);

// A geodesic sphere: the icosahedron refined `level` times 1-to-4 with the new
// vertices pushed onto the sphere (20 * 4^level faces). Level 0 is the icosahedron.
Mesh make_geodesic_sphere(const Vec3& center, double radius, int level);

// Throws InvalidSeed unless the mesh is a non-empty, closed, 2-manifold triangle mesh
// with finite coordinates.
void check_seed_mesh(const Mesh& mesh);

}  // namespace gdm
